#pragma once
// The SQL of a fleet (schema/db/postgres/0004_cluster.sql): node heartbeats and session leases.
// Every time is the database's clock, so nodes never compare their own clocks. Acquiring a lease is
// one statement that succeeds only if nobody else holds it unexpired: two nodes can never both win.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "storage/database.hpp"

namespace pslam::server {

struct NodeRow {
  std::string node_id;
  std::string address;
  double started_at = 0.0;
  double heartbeat_age = 0.0;  // seconds since its last heartbeat
  std::int64_t running_sessions = 0;
  std::int64_t max_sessions = 0;
  std::int64_t agents = 0;
  std::int64_t viewers = 0;
};

struct LeaseRow {
  std::string session_id;
  std::string node_id;
  std::int64_t epoch = 0;
  double expires_in = 0.0;  // seconds; negative once expired
};

struct NodeLoad {
  std::int64_t running_sessions = 0;
  std::int64_t max_sessions = 0;
  std::int64_t agents = 0;
  std::int64_t viewers = 0;
};

class ClusterRepository {
 public:
  explicit ClusterRepository(Database& db) : db_(db) {}

  double Now();
  // Registers the node or refreshes its heartbeat and load.
  void Heartbeat(const std::string& node_id, const std::string& address, const NodeLoad& load);
  // A node leaving cleanly: its row and its leases go, so others take its sessions at once.
  void Leave(const std::string& node_id);
  // Nodes whose heartbeat is at most 'alive_within' seconds old.
  std::vector<NodeRow> Nodes(double alive_within);

  // Extends every lease the node holds to now + lease_seconds; returns the sessions it still holds.
  // An expired lease nobody took is still the node's: taking it would have changed its owner.
  std::vector<std::string> RenewLeases(const std::string& node_id, double lease_seconds);
  // Takes the session's lease if it is free, expired or already the node's. The new epoch, or none.
  std::optional<std::int64_t> TryAcquire(const std::string& session_id, const std::string& node_id,
                                         double lease_seconds);
  void Release(const std::string& session_id, const std::string& node_id);
  // True if the node holds the lease at 'epoch'; locks the row until the transaction ends.
  bool HoldsLease(const std::string& session_id, const std::string& node_id, std::int64_t epoch);
  std::optional<LeaseRow> Lease(const std::string& session_id);
  std::vector<LeaseRow> Leases();
  // Active sessions whose lease is missing or expired: nobody runs them.
  std::vector<std::string> Orphans();

 private:
  Database& db_;
};

}  // namespace pslam::server
