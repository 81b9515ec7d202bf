#include "cluster/cluster_repository.hpp"

namespace pslam::server {
namespace {

// The database's clock in unix seconds (PostgreSQL: the time of the statement, not of the transaction).
constexpr const char* kNow = "CAST(EXTRACT(EPOCH FROM clock_timestamp()) AS DOUBLE PRECISION)";

std::string WithNow(std::string sql) {
  for (std::size_t at; (at = sql.find("{now}")) != std::string::npos;) sql.replace(at, 5, kNow);
  return sql;
}

LeaseRow ReadLease(Statement& s) {
  return {s.Text(0), s.Text(1), s.Int64(2), s.Double(3)};
}

}  // namespace

double ClusterRepository::Now() {
  auto s = db_.Prepare(WithNow("SELECT {now}"));
  s.Step();
  return s.Double(0);
}

void ClusterRepository::Heartbeat(const std::string& node_id, const std::string& address, const NodeLoad& load) {
  db_.Prepare(WithNow(
                  "INSERT INTO cluster_nodes (node_id, address, started_at, heartbeat_at, running_sessions, max_sessions, "
                  "agents, viewers) VALUES (?, ?, {now}, {now}, ?, ?, ?, ?) ON CONFLICT (node_id) DO UPDATE SET "
                  "address = EXCLUDED.address, heartbeat_at = EXCLUDED.heartbeat_at, running_sessions = "
                  "EXCLUDED.running_sessions, max_sessions = EXCLUDED.max_sessions, agents = EXCLUDED.agents, "
                  "viewers = EXCLUDED.viewers"))
      .BindAll(node_id, address, load.running_sessions, load.max_sessions, load.agents, load.viewers)
      .Run();
}

void ClusterRepository::Leave(const std::string& node_id) {
  db_.Prepare("DELETE FROM session_leases WHERE node_id = ?").BindAll(node_id).Run();
  db_.Prepare("DELETE FROM cluster_nodes WHERE node_id = ?").BindAll(node_id).Run();
}

std::vector<NodeRow> ClusterRepository::Nodes(double alive_within) {
  auto s = db_.Prepare(WithNow(
      "SELECT node_id, address, started_at, {now} - heartbeat_at, running_sessions, max_sessions, agents, viewers "
      "FROM cluster_nodes WHERE heartbeat_at >= {now} - ? ORDER BY node_id"));
  s.BindAll(alive_within);
  std::vector<NodeRow> rows;
  while (s.Step()) {
    rows.push_back({s.Text(0), s.Text(1), s.Double(2), s.Double(3), s.Int64(4), s.Int64(5), s.Int64(6), s.Int64(7)});
  }
  return rows;
}

std::vector<std::string> ClusterRepository::RenewLeases(const std::string& node_id, double lease_seconds) {
  // One row per statement, each its own transaction: a renewal never holds one lease row while
  // waiting for another. A single UPDATE of every row would, and with a writer's batch holding
  // those rows FOR SHARE in another order the two deadlock.
  std::vector<std::string> ids;
  {
    auto s = db_.Prepare("SELECT session_id FROM session_leases WHERE node_id = ?");
    s.BindAll(node_id);
    while (s.Step()) ids.push_back(s.Text(0));
  }
  std::vector<std::string> held;
  for (const std::string& id : ids) {
    auto s = db_.Prepare(WithNow(
        "UPDATE session_leases SET expires_at = {now} + ? WHERE session_id = ? AND node_id = ? RETURNING session_id"));
    s.BindAll(lease_seconds, id, node_id);
    if (s.Step()) held.push_back(s.Text(0));
  }
  return held;
}

std::optional<std::int64_t> ClusterRepository::TryAcquire(const std::string& session_id, const std::string& node_id,
                                                          double lease_seconds) {
  // One statement: the row lock taken by the upsert serialises two nodes racing for the session.
  auto s = db_.Prepare(WithNow(
      "INSERT INTO session_leases (session_id, node_id, epoch, expires_at) VALUES (?, ?, 1, {now} + ?) "
      "ON CONFLICT (session_id) DO UPDATE SET node_id = EXCLUDED.node_id, expires_at = EXCLUDED.expires_at, "
      "epoch = session_leases.epoch + CASE WHEN session_leases.node_id = EXCLUDED.node_id THEN 0 ELSE 1 END "
      "WHERE session_leases.node_id = EXCLUDED.node_id OR session_leases.expires_at <= {now} RETURNING epoch"));
  s.BindAll(session_id, node_id, lease_seconds);
  if (!s.Step()) return std::nullopt;
  return s.Int64(0);
}

void ClusterRepository::Release(const std::string& session_id, const std::string& node_id) {
  db_.Prepare("DELETE FROM session_leases WHERE session_id = ? AND node_id = ?").BindAll(session_id, node_id).Run();
}

bool ClusterRepository::HoldsLease(const std::string& session_id, const std::string& node_id, std::int64_t epoch) {
  auto s = db_.Prepare("SELECT 1 FROM session_leases WHERE session_id = ? AND node_id = ? AND epoch = ? FOR SHARE");
  s.BindAll(session_id, node_id, epoch);
  return s.Step();
}

std::optional<LeaseRow> ClusterRepository::Lease(const std::string& session_id) {
  auto s = db_.Prepare(
      WithNow("SELECT session_id, node_id, epoch, expires_at - {now} FROM session_leases WHERE session_id = ?"));
  s.BindAll(session_id);
  if (!s.Step()) return std::nullopt;
  return ReadLease(s);
}

std::vector<LeaseRow> ClusterRepository::Leases() {
  auto s = db_.Prepare(WithNow("SELECT session_id, node_id, epoch, expires_at - {now} FROM session_leases "
                               "ORDER BY node_id, session_id"));
  std::vector<LeaseRow> rows;
  while (s.Step()) rows.push_back(ReadLease(s));
  return rows;
}

std::vector<std::string> ClusterRepository::Orphans() {
  auto s = db_.Prepare(WithNow(
      "SELECT s.id FROM sessions s LEFT JOIN session_leases l ON l.session_id = s.id "
      "WHERE s.status = 'active' AND (l.session_id IS NULL OR l.expires_at <= {now}) ORDER BY s.created_at, s.id"));
  std::vector<std::string> ids;
  while (s.Step()) ids.push_back(s.Text(0));
  return ids;
}

}  // namespace pslam::server
