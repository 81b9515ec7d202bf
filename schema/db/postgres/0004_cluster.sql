-- A fleet of server nodes on one database. Each node says it is alive with a heartbeat; a session
-- is run by the one node holding its lease. Times are the database's clock (unix seconds), so the
-- nodes' own clocks never have to agree.
CREATE TABLE cluster_nodes (
  node_id          TEXT PRIMARY KEY,
  address          TEXT NOT NULL,              -- HOST:PORT where agents and viewers reach the node
  started_at       DOUBLE PRECISION NOT NULL,
  heartbeat_at     DOUBLE PRECISION NOT NULL,
  running_sessions BIGINT NOT NULL DEFAULT 0,
  max_sessions     BIGINT NOT NULL DEFAULT 0,
  agents           BIGINT NOT NULL DEFAULT 0,
  viewers          BIGINT NOT NULL DEFAULT 0
);

-- Who runs a session. epoch grows by one at every change of owner; expires_at is renewed by the
-- owner's heartbeat. Another node may take the session only once expires_at has passed.
CREATE TABLE session_leases (
  session_id TEXT PRIMARY KEY REFERENCES sessions (id) ON DELETE CASCADE,
  node_id    TEXT NOT NULL,
  epoch      BIGINT NOT NULL,
  expires_at DOUBLE PRECISION NOT NULL
);
CREATE INDEX session_leases_by_node ON session_leases (node_id);
