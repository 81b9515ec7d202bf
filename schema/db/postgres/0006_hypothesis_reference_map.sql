-- The site map a hypothesis took its reference from, when not the session's own map: a mapping
-- session of a site searches the site's stored maps too.
ALTER TABLE hypotheses ADD COLUMN reference_site TEXT;
ALTER TABLE hypotheses ADD COLUMN reference_version BIGINT;
