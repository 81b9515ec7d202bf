#pragma once
// One node of a fleet that shares a PostgreSQL database (docs/fleet.md). A session runs on the one
// node that holds its lease; this node heartbeats, renews its leases, lets go of a session whose
// lease it lost, and takes over sessions nobody runs (their owner died, or left) when placement
// picks it: the least loaded live node. Two threads: one only heartbeats, renews and looks for
// orphans, so nothing slow can let a lease lapse; the other runs posted work (an agent's claim)
// and the hooks, which rebuild or stop sessions and may wait for storage. Neither is a network
// thread.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cluster/cluster_repository.hpp"
#include "common/result.hpp"

namespace pslam::server {

class SessionRepository;
struct InputRecord;

struct ClusterOptions {
  std::string node_id;
  std::string address;          // HOST:PORT where agents and viewers reach this node
  double lease_seconds = 5.0;   // a dead node's sessions move after at most this long
};

// Thrown by a fenced write of a node that no longer holds the session's lease.
inline constexpr const char* kLeaseLost = "lease lost";

// Where a session should run.
struct Placement {
  enum class Kind { kHere, kElsewhere, kUnavailable } kind = Kind::kHere;
  std::string node_id;
  std::string address;       // kElsewhere: where to go
  std::int64_t epoch = 0;    // kHere after a claim: the lease's epoch
  std::string reason;        // kUnavailable

  static Placement Here(std::string node_id, std::int64_t epoch = 0) {
    Placement p;
    p.node_id = std::move(node_id);
    p.epoch = epoch;
    return p;
  }
  static Placement Elsewhere(std::string node_id, std::string address) {
    Placement p;
    p.kind = Kind::kElsewhere;
    p.node_id = std::move(node_id);
    p.address = std::move(address);
    return p;
  }
  static Placement Unavailable(std::string reason) {
    Placement p;
    p.kind = Kind::kUnavailable;
    p.reason = std::move(reason);
    return p;
  }
};

struct ClusterView {
  std::string node_id;
  double lease_seconds = 0.0;
  std::vector<NodeRow> nodes;
  std::vector<LeaseRow> leases;
};

class ClusterCoordinator {
 public:
  struct Hooks {
    std::function<NodeLoad()> load;
    // The node lost the session's lease (taken over, or renewals failed too long): stop running it.
    std::function<void(const std::string& session_id)> lost;
    // The node won the lease of a session nobody ran: rebuild and resume it.
    std::function<void(const std::string& session_id, std::int64_t epoch)> adopt;
    // Rebalancing: stop running the session here with a checkpoint, every write of it committed,
    // and tell its agent to reconnect; false if it no longer runs here. The lease goes after.
    std::function<bool(const std::string& session_id)> hand_over;
  };

  // Connects, registers the node (so it is visible at once) and starts the thread.
  static Result<std::unique_ptr<ClusterCoordinator>> Start(ClusterOptions options, const std::string& postgres_url,
                                                           Hooks hooks);
  ~ClusterCoordinator();
  ClusterCoordinator(const ClusterCoordinator&) = delete;
  ClusterCoordinator& operator=(const ClusterCoordinator&) = delete;

  // Runs 'work' on the coordinator's work thread, in order with the hooks.
  void Post(std::function<void(ClusterCoordinator&)> work);

  // ---- On the coordinator thread (inside Post) or REST worker threads; they reach the database. ----
  // A new session: here, or the least loaded live node.
  Placement PlaceNew();
  // A stored session this node does not run: its live owner, or (nobody runs it) this node: the
  // lease is taken, the session counted as running here, and the result carries the epoch.
  Placement Claim(const std::string& session_id);
  // The address of the live node other than this one that holds the session's lease, if any.
  std::optional<std::string> OwnerElsewhere(const std::string& session_id);
  ClusterView View();

  // ---- Bookkeeping of what runs here (any thread, no database) ----
  void Owned(const std::string& session_id, std::int64_t epoch);
  // The session stopped running here (closed, deleted, lost): its lease is given back.
  void Released(const std::string& session_id);

  // Takes the session's lease inside the caller's transaction (the one creating the session), so a
  // new session is never without an owner, and counts it as running here (a rolled-back one is
  // let go at the next renewal). Throws StorageError if another node holds it.
  std::int64_t AcquireIn(Database& db, const std::string& session_id);
  // Fences a write: throws StorageError(kLeaseLost) unless this node still holds the lease at
  // 'epoch'. The row lock it takes holds off a takeover until the caller's transaction ends.
  void CheckLeaseIn(Database& db, const std::string& session_id, std::int64_t epoch) const;
  // Stores an input fenced the same way, in one statement (one round trip to the database).
  void InsertInputIn(SessionRepository& repo, const std::string& session_id, std::int64_t epoch,
                     const InputRecord& input) const;

  // Stops the thread: no more heartbeats, renewals or takeovers (a node shutting down).
  void Stop();
  // Leaves the fleet cleanly, after the node's last write: its row and leases go at once, so the
  // other nodes take its sessions now rather than when the leases expire.
  void Leave();

  const ClusterOptions& options() const { return options_; }

 private:
  ClusterCoordinator(ClusterOptions options, Database db, Hooks hooks);
  void TickLoop();
  void WorkLoop();
  void Tick();
  void RenewOrFence();
  void AdoptOrphans();
  // One session to a less loaded node, if this node is the fullest (cluster_rebalance.cpp).
  void Rebalance();
  std::optional<std::string> SessionToHandOver(std::chrono::steady_clock::time_point now);
  void HandOver(const std::string& session_id, const NodeRow& to);
  // The node a session was just handed to, while it should be taking the session over.
  std::optional<NodeRow> HandedTo(const std::string& session_id);
  // Live nodes with this node's own load made current and recent placements counted.
  std::vector<NodeRow> LiveNodes();
  const NodeRow* LeastLoaded(const std::vector<NodeRow>& nodes) const;

  const ClusterOptions options_;
  Hooks hooks_;

  std::mutex db_mutex_;  // the connection is used by one thread at a time
  Database db_;
  ClusterRepository repo_;

  std::mutex mutex_;  // guards what follows
  std::condition_variable wake_;
  std::deque<std::function<void(ClusterCoordinator&)>> work_;
  std::map<std::string, std::int64_t> owned_;  // sessions running here, by lease epoch
  std::set<std::string> released_;             // leases to give back at the next tick
  std::map<std::string, std::pair<int, std::chrono::steady_clock::time_point>> recent_placements_;
  std::map<std::string, std::chrono::steady_clock::time_point> orphan_since_;
  std::chrono::steady_clock::time_point last_renewal_;
  // Rebalancing: since when each session has run here (first seen), the last hand-over, and where
  // recent ones went (this node sends their agents there and does not take them back meanwhile).
  std::map<std::string, std::chrono::steady_clock::time_point> held_since_;
  std::chrono::steady_clock::time_point last_hand_over_;
  std::map<std::string, std::pair<NodeRow, std::chrono::steady_clock::time_point>> handed_over_;
  bool handing_over_ = false;
  bool stopping_ = false;
  std::thread ticker_, worker_;
};

}  // namespace pslam::server
