-- Sites (a building, a floor) and their versioned maps, as ../0003_sites.sql in PostgreSQL's types. A version is stored as the map_server
-- files themselves, byte for byte: exporting a version gives back exactly what was imported, and a
-- version made from a session is what that session's map.pgm / map.yaml served when it closed.
CREATE TABLE sites (
  id         TEXT PRIMARY KEY,               -- "site-" + 16 hex digits
  name       TEXT NOT NULL,
  created_at DOUBLE PRECISION NOT NULL
);

CREATE TABLE site_maps (
  site_id    TEXT NOT NULL REFERENCES sites (id) ON DELETE CASCADE,
  version    BIGINT NOT NULL,               -- 1, 2, 3, ... per site
  created_at DOUBLE PRECISION NOT NULL,
  source     TEXT NOT NULL,                  -- session | import
  session_id TEXT,                           -- source session: no foreign key, the map outlives it
  note       TEXT NOT NULL DEFAULT '',
  resolution DOUBLE PRECISION NOT NULL,
  width      BIGINT NOT NULL,               -- image size in pixels
  height     BIGINT NOT NULL,
  origin_x   DOUBLE PRECISION NOT NULL,                  -- world position of the lower-left pixel corner
  origin_y   DOUBLE PRECISION NOT NULL,
  yaml       TEXT NOT NULL,                  -- the map_server YAML, as given
  pgm        BYTEA NOT NULL,                  -- its PGM image, as given
  PRIMARY KEY (site_id, version)
);
