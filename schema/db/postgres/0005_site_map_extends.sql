-- The version an extend session started from, for a version it produced (NULL otherwise).
ALTER TABLE site_maps ADD COLUMN extends_version BIGINT;
