// Rebalancing (docs/fleet.md): a node that joins or comes back only gets new sessions and orphans,
// so after failovers sessions crowd on the survivors. The fullest node hands one session at a time
// to the least loaded one when it runs at least two more, with a cooldown: it checkpoints and stops
// the session, gives its lease back, and its agent, told to reconnect, is sent to that node, which
// takes the orphan over. Fencing keeps every input stored and filtered once, as in a failover.
#include <algorithm>
#include <iostream>

#include "cluster/cluster_coordinator.hpp"

namespace pslam::server {
namespace {

using Clock = std::chrono::steady_clock;

std::chrono::duration<double> Seconds(double s) { return std::chrono::duration<double>(s); }

}  // namespace

void ClusterCoordinator::Rebalance() {
  const auto now = Clock::now();
  // Two leases: long enough for the new owner to take the session and report it in a heartbeat.
  const auto cooldown = Seconds(2 * options_.lease_seconds);
  {
    std::lock_guard lock(mutex_);
    std::erase_if(handed_over_, [&](const auto& h) { return now - h.second.second > cooldown; });
    if (handing_over_ || now - last_hand_over_ < cooldown) return;
  }
  if (!hooks_.hand_over) return;
  const auto nodes = LiveNodes();
  const NodeRow* fullest = nullptr;
  for (const auto& n : nodes) {
    // The most sessions; of equals the first by id, so only one of them hands one over.
    if (!fullest || n.running_sessions > fullest->running_sessions ||
        (n.running_sessions == fullest->running_sessions && n.node_id < fullest->node_id)) {
      fullest = &n;
    }
  }
  const NodeRow* target = LeastLoaded(nodes);
  if (!fullest || !target || fullest->node_id != options_.node_id || target->node_id == options_.node_id) return;
  if (fullest->running_sessions < target->running_sessions + 2) return;  // one move would not even them
  const auto session = SessionToHandOver(now);
  if (!session) return;
  {
    std::lock_guard lock(mutex_);
    handing_over_ = true;
    last_hand_over_ = now;
    handed_over_[*session] = {*target, now};
  }
  Post([id = *session, to = *target](ClusterCoordinator& c) { c.HandOver(id, to); });
}

std::optional<std::string> ClusterCoordinator::SessionToHandOver(Clock::time_point now) {
  std::lock_guard lock(mutex_);
  std::erase_if(held_since_, [&](const auto& h) { return !owned_.count(h.first); });
  for (const auto& [id, epoch] : owned_) held_since_.try_emplace(id, now);
  // The one that has run here longest, and for two leases at least: a session that just arrived
  // (handed over, or taken over) is not moved again at once.
  std::optional<std::string> oldest;
  Clock::time_point since = now - std::chrono::duration_cast<Clock::duration>(Seconds(2 * options_.lease_seconds));
  for (const auto& [id, t] : held_since_) {
    if (t <= since) {
      since = t;
      oldest = id;
    }
  }
  return oldest;
}

void ClusterCoordinator::HandOver(const std::string& session_id, const NodeRow& to) {
  bool stopped = false;
  try {
    stopped = hooks_.hand_over(session_id);
  } catch (const std::exception& e) {
    stopped = true;  // it was taken out of running first: it no longer runs here
    std::cerr << "cluster: handing session " << session_id << " over: " << e.what() << "\n";
  }
  bool released = false;
  if (stopped) {
    try {
      std::lock_guard lock(db_mutex_);
      repo_.Release(session_id, options_.node_id);
      released = true;
    } catch (const std::exception& e) {
      std::cerr << "cluster: giving back the lease of session " << session_id << " failed: " << e.what() << "\n";
    }
  }
  std::lock_guard lock(mutex_);
  handing_over_ = false;
  if (!stopped) {
    handed_over_.erase(session_id);
    return;
  }
  owned_.erase(session_id);
  if (!released) released_.insert(session_id);  // the next renewal tries again
  std::cerr << "cluster: handed session " << session_id << " over to " << to.node_id << " (rebalancing)\n";
}

std::optional<NodeRow> ClusterCoordinator::HandedTo(const std::string& session_id) {
  std::lock_guard lock(mutex_);
  const auto it = handed_over_.find(session_id);
  if (it == handed_over_.end() || Clock::now() - it->second.second > Seconds(2 * options_.lease_seconds)) {
    return std::nullopt;
  }
  return it->second.first;
}

}  // namespace pslam::server
