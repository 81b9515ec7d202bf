-- The fleet tables of postgres/0004_cluster.sql, so both engines keep one schema. A SQLite server
-- is a single node and leaves them empty: a fleet shares PostgreSQL.
CREATE TABLE cluster_nodes (
  node_id          TEXT PRIMARY KEY,
  address          TEXT NOT NULL,              -- HOST:PORT where agents and viewers reach the node
  started_at       REAL NOT NULL,
  heartbeat_at     REAL NOT NULL,
  running_sessions INTEGER NOT NULL DEFAULT 0,
  max_sessions     INTEGER NOT NULL DEFAULT 0,
  agents           INTEGER NOT NULL DEFAULT 0,
  viewers          INTEGER NOT NULL DEFAULT 0
);

-- Who runs a session. epoch grows by one at every change of owner; expires_at is renewed by the
-- owner's heartbeat. Another node may take the session only once expires_at has passed.
CREATE TABLE session_leases (
  session_id TEXT PRIMARY KEY REFERENCES sessions (id) ON DELETE CASCADE,
  node_id    TEXT NOT NULL,
  epoch      INTEGER NOT NULL,
  expires_at REAL NOT NULL
);
CREATE INDEX session_leases_by_node ON session_leases (node_id);
