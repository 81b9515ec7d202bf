-- Initial schema of the pslam-server database. Times are Unix seconds (REAL). Applied by
-- server/src/storage/migrate.cpp inside one transaction with PRAGMA user_version = 1.

-- One mapping session: an agent's run, a session created through the API, or a replay.
CREATE TABLE sessions (
  id            TEXT PRIMARY KEY,             -- "s-" + 16 hex digits
  name          TEXT NOT NULL DEFAULT '',
  robot_id      TEXT NOT NULL DEFAULT '',
  source        TEXT NOT NULL,                -- agent | api | replay
  replay_of     TEXT,                         -- replays: the source session id or log path
  status        TEXT NOT NULL,                -- active | closed | failed
  created_at    REAL NOT NULL,
  updated_at    REAL NOT NULL,
  closed_at     REAL,
  laser_json    TEXT NOT NULL,                -- the hello's laser object
  settings_json TEXT NOT NULL,                -- the effective mapping settings
  processed_seq INTEGER NOT NULL DEFAULT 0,   -- inputs covered by the stored map and trajectory
  scans         INTEGER NOT NULL DEFAULT 0,   -- scans processed at the last checkpoint
  stats_json    TEXT NOT NULL DEFAULT '{}',   -- statistics at the last checkpoint
  metrics_json  TEXT NOT NULL DEFAULT '{}'    -- replays: RPE / KL against a reference
);
CREATE INDEX sessions_by_created ON sessions (created_at);
CREATE INDEX sessions_by_status ON sessions (status, created_at);

-- Every raw input, as received: the filter can be rebuilt from these alone (resume, replay).
CREATE TABLE inputs (
  session_id TEXT NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  seq        INTEGER NOT NULL,
  kind       INTEGER NOT NULL,                -- 1 odometry, 2 scan
  t          REAL NOT NULL,
  x          REAL NOT NULL,
  y          REAL NOT NULL,
  theta      REAL NOT NULL,
  v          REAL NOT NULL DEFAULT 0,
  w          REAL NOT NULL DEFAULT 0,
  ranges     BLOB,                            -- scans: float32 little-endian, NaN = no return
  stamp      TEXT,                            -- the source's timestamp text, when it has one
  PRIMARY KEY (session_id, seq)
) WITHOUT ROWID;

-- The pose estimate at every scan; replaced by the best particle's trajectory when a session closes.
CREATE TABLE trajectory (
  session_id TEXT NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  scan_index INTEGER NOT NULL,
  seq        INTEGER NOT NULL,
  t          REAL NOT NULL,
  stamp      TEXT,
  x          REAL NOT NULL,
  y          REAL NOT NULL,
  theta      REAL NOT NULL,
  PRIMARY KEY (session_id, scan_index)
) WITHOUT ROWID;

-- Periodic map checkpoints. Tiles are written incrementally: a checkpoint rewrites only the tiles
-- that changed since the previous one, so map_tiles always holds the latest checkpoint's map.
CREATE TABLE map_snapshots (
  id            INTEGER PRIMARY KEY,
  session_id    TEXT NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  created_at    REAL NOT NULL,
  processed_seq INTEGER NOT NULL,
  scans         INTEGER NOT NULL,
  resolution    REAL NOT NULL,
  tiles_written INTEGER NOT NULL
);
CREATE INDEX map_snapshots_by_session ON map_snapshots (session_id, id);

CREATE TABLE map_tiles (
  session_id  TEXT NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  tx          INTEGER NOT NULL,               -- tile index: cells tx*size .. tx*size+size-1
  ty          INTEGER NOT NULL,
  size        INTEGER NOT NULL,               -- cells per side (64)
  revision    INTEGER NOT NULL,
  snapshot_id INTEGER NOT NULL,
  data        BLOB NOT NULL,                  -- zlib(int16 little-endian log-odds x size*size)
  PRIMARY KEY (session_id, tx, ty)
) WITHOUT ROWID;

-- Structure predictions (P-SLAM), every field of the predictor's record.
CREATE TABLE hypotheses (
  session_id    TEXT NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  id            INTEGER NOT NULL,
  t             REAL NOT NULL,
  target_cx     INTEGER NOT NULL,
  target_cy     INTEGER NOT NULL,
  reference_cx  INTEGER NOT NULL,
  reference_cy  INTEGER NOT NULL,
  theta         REAL NOT NULL,
  translation_x REAL NOT NULL,
  translation_y REAL NOT NULL,
  psi           REAL NOT NULL,
  area          REAL NOT NULL,
  cells         BLOB NOT NULL,                -- zlib((int32 x, int32 y, float32 occupancy) x n)
  cell_count    INTEGER NOT NULL,
  min_x         REAL NOT NULL,                -- world bounding box of the cells, for bbox filters
  min_y         REAL NOT NULL,
  max_x         REAL NOT NULL,
  max_y         REAL NOT NULL,
  status        TEXT NOT NULL,
  hit_ratio     REAL NOT NULL,
  psi_observed  REAL NOT NULL,
  updated_at    REAL NOT NULL,
  PRIMARY KEY (session_id, id)
) WITHOUT ROWID;
CREATE INDEX hypotheses_by_status ON hypotheses (session_id, status);

CREATE TABLE hypothesis_status (
  id            INTEGER PRIMARY KEY,
  session_id    TEXT NOT NULL REFERENCES sessions (id) ON DELETE CASCADE,
  hypothesis_id INTEGER NOT NULL,
  t             REAL NOT NULL,
  status        TEXT NOT NULL,
  hit_ratio     REAL NOT NULL,
  psi_observed  REAL NOT NULL
);
CREATE INDEX hypothesis_status_by_hypothesis ON hypothesis_status (session_id, hypothesis_id, id);

-- What happened: session lifecycle, agent connections, refused requests. session_id is NULL for
-- server-wide events, so it has no foreign key; deleting a session deletes its events explicitly.
CREATE TABLE events (
  id         INTEGER PRIMARY KEY,
  session_id TEXT,
  t          REAL NOT NULL,
  kind       TEXT NOT NULL,
  detail     TEXT NOT NULL DEFAULT '{}'
);
CREATE INDEX events_by_session ON events (session_id, id);
