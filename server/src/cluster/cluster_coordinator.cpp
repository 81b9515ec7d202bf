#include "cluster/cluster_coordinator.hpp"

#include <algorithm>
#include <iostream>
#include <tuple>

#include "storage/session_repository.hpp"

namespace pslam::server {
namespace {

using Clock = std::chrono::steady_clock;

std::chrono::duration<double> Seconds(double s) { return std::chrono::duration<double>(s); }

// A node's share of its capacity in use; a node at its maximum takes nothing more.
double Fill(const NodeRow& n) {
  return static_cast<double>(n.running_sessions) / static_cast<double>(std::max<std::int64_t>(1, n.max_sessions));
}

[[noreturn]] void ThrowLeaseLost(const std::string& session_id) {
  throw StorageError(std::string(kLeaseLost) + ": another node runs session " + session_id + " now");
}

}  // namespace

ClusterCoordinator::ClusterCoordinator(ClusterOptions options, Database db, Hooks hooks)
    : options_(std::move(options)), hooks_(std::move(hooks)), db_(std::move(db)), repo_(db_) {}

Result<std::unique_ptr<ClusterCoordinator>> ClusterCoordinator::Start(ClusterOptions options,
                                                                      const std::string& postgres_url, Hooks hooks) {
  try {
    std::unique_ptr<ClusterCoordinator> c(
        new ClusterCoordinator(std::move(options), Database::Connect(postgres_url), std::move(hooks)));
    // Leases of an earlier run of this node are stale: its sessions go to whoever takes them now.
    c->repo_.Leave(c->options_.node_id);
    c->repo_.Heartbeat(c->options_.node_id, c->options_.address, c->hooks_.load());
    c->last_renewal_ = Clock::now();
    c->ticker_ = std::thread([raw = c.get()] { raw->TickLoop(); });
    c->worker_ = std::thread([raw = c.get()] { raw->WorkLoop(); });
    return c;
  } catch (const std::exception& e) {
    return Error{std::string("cluster: ") + e.what()};
  }
}

ClusterCoordinator::~ClusterCoordinator() { Stop(); }

void ClusterCoordinator::Stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (ticker_.joinable()) ticker_.join();
  if (worker_.joinable()) worker_.join();
}

void ClusterCoordinator::Leave() {
  Stop();
  try {
    std::lock_guard lock(db_mutex_);
    repo_.Leave(options_.node_id);
  } catch (const std::exception& e) {
    std::cerr << "cluster: leaving failed (the leases expire instead): " << e.what() << "\n";
  }
}

void ClusterCoordinator::Post(std::function<void(ClusterCoordinator&)> work) {
  {
    std::lock_guard lock(mutex_);
    work_.push_back(std::move(work));
  }
  wake_.notify_all();
}

void ClusterCoordinator::TickLoop() {
  // Five renewals per lease: a lease survives a few slow or failed ones.
  const auto period = std::chrono::duration_cast<Clock::duration>(Seconds(std::max(0.1, options_.lease_seconds / 5)));
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, period, [&] { return stopping_; })) {
    lock.unlock();
    Tick();
    lock.lock();
  }
}

void ClusterCoordinator::WorkLoop() {
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [&] { return stopping_ || !work_.empty(); });
    if (stopping_) return;
    auto job = std::move(work_.front());
    work_.pop_front();
    lock.unlock();
    try {
      job(*this);
    } catch (const std::exception& e) {
      std::cerr << "cluster: " << e.what() << "\n";
    }
    lock.lock();
  }
}

void ClusterCoordinator::Tick() {
  try {
    std::lock_guard lock(db_mutex_);
    repo_.Heartbeat(options_.node_id, options_.address, hooks_.load());
  } catch (const std::exception& e) {
    std::cerr << "cluster: heartbeat failed: " << e.what() << "\n";
  }
  RenewOrFence();
  try {
    AdoptOrphans();
    Rebalance();
  } catch (const std::exception& e) {
    std::cerr << "cluster: takeover or rebalancing check failed: " << e.what() << "\n";
  }
}

void ClusterCoordinator::RenewOrFence() {
  std::set<std::string> released;
  {
    std::lock_guard lock(mutex_);
    released.swap(released_);
  }
  std::vector<std::string> lost;
  try {
    std::vector<std::string> held;
    {
      std::lock_guard lock(db_mutex_);
      for (const auto& id : released) repo_.Release(id, options_.node_id);
      held = repo_.RenewLeases(options_.node_id, options_.lease_seconds);
    }
    std::sort(held.begin(), held.end());
    std::lock_guard lock(mutex_);
    last_renewal_ = Clock::now();
    // Held but not run here (a creation that rolled back after taking it): give it back.
    for (const auto& id : held) {
      if (!owned_.count(id)) released_.insert(id);
    }
    for (auto it = owned_.begin(); it != owned_.end();) {
      if (std::binary_search(held.begin(), held.end(), it->first)) {
        ++it;
      } else {
        lost.push_back(it->first);
        it = owned_.erase(it);
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "cluster: renewing leases failed: " << e.what() << "\n";
    std::lock_guard lock(mutex_);
    released_.insert(released.begin(), released.end());
    // Past this the leases may expire and another node take the sessions: stop first.
    if (Clock::now() - last_renewal_ > Seconds(0.6 * options_.lease_seconds)) {
      for (const auto& [id, epoch] : owned_) lost.push_back(id);
      owned_.clear();
    }
  }
  for (const auto& id : lost) {
    std::cerr << "cluster: lost the lease of session " << id << ", stopping it here\n";
    Post([id](ClusterCoordinator& c) { c.hooks_.lost(id); });
  }
}

void ClusterCoordinator::AdoptOrphans() {
  std::vector<std::string> orphans;
  std::vector<NodeRow> nodes;
  {
    std::lock_guard lock(db_mutex_);
    orphans = repo_.Orphans();
  }
  if (orphans.empty()) {
    std::lock_guard lock(mutex_);
    orphan_since_.clear();
    return;
  }
  nodes = LiveNodes();
  const auto now = Clock::now();
  std::vector<std::pair<std::string, std::int64_t>> adopted;
  {
    std::lock_guard lock(mutex_);
    std::map<std::string, Clock::time_point> seen;
    for (const auto& id : orphans) seen[id] = orphan_since_.count(id) ? orphan_since_[id] : now;
    orphan_since_.swap(seen);
  }
  // Every node deals the orphans out the same way, least loaded first; each takes its own. One
  // left orphaned for two leases (its node is full, or not taking) goes to whoever sees it.
  for (const auto& id : orphans) {
    const NodeRow* target = LeastLoaded(nodes);
    bool mine = target && target->node_id == options_.node_id;
    {
      std::lock_guard lock(mutex_);
      if (owned_.count(id)) mine = true;  // ours, its lease row lost: take it back
      if (handed_over_.count(id)) mine = false;  // just handed to another node: let it take it
      if (now - orphan_since_[id] > Seconds(2 * options_.lease_seconds)) mine = true;
    }
    if (target) const_cast<NodeRow*>(target)->running_sessions++;
    if (!mine) continue;
    std::optional<std::int64_t> epoch;
    {
      std::lock_guard lock(db_mutex_);
      epoch = repo_.TryAcquire(id, options_.node_id, options_.lease_seconds);
    }
    if (epoch) adopted.emplace_back(id, *epoch);
  }
  for (const auto& [id, epoch] : adopted) {
    bool running_here;
    {
      std::lock_guard lock(mutex_);
      running_here = owned_.count(id) > 0;
      owned_[id] = epoch;
    }
    if (running_here) continue;
    std::cerr << "cluster: took over session " << id << " (lease epoch " << epoch << ")\n";
    Post([id, epoch](ClusterCoordinator& c) { c.hooks_.adopt(id, epoch); });
  }
}

std::vector<NodeRow> ClusterCoordinator::LiveNodes() {
  std::vector<NodeRow> nodes;
  {
    std::lock_guard lock(db_mutex_);
    nodes = repo_.Nodes(options_.lease_seconds);
  }
  const NodeLoad own = hooks_.load();
  auto self = std::find_if(nodes.begin(), nodes.end(), [&](const NodeRow& n) { return n.node_id == options_.node_id; });
  if (self == nodes.end()) {
    NodeRow row;
    row.node_id = options_.node_id;
    row.address = options_.address;
    self = nodes.insert(nodes.end(), row);
  }
  self->running_sessions = own.running_sessions;
  self->max_sessions = own.max_sessions;
  // Sessions sent to a node that has not reported them in a heartbeat yet.
  std::lock_guard lock(mutex_);
  const auto now = Clock::now();
  std::erase_if(recent_placements_, [&](const auto& p) { return now - p.second.second > Seconds(options_.lease_seconds); });
  for (auto& n : nodes) {
    if (const auto it = recent_placements_.find(n.node_id); it != recent_placements_.end()) {
      n.running_sessions += it->second.first;
    }
  }
  return nodes;
}

const NodeRow* ClusterCoordinator::LeastLoaded(const std::vector<NodeRow>& nodes) const {
  // Least filled, then fewest sessions, then this node (no needless redirect), then by id.
  const auto key = [&](const NodeRow& n) {
    return std::make_tuple(Fill(n), n.running_sessions, n.node_id != options_.node_id, n.node_id);
  };
  const NodeRow* best = nullptr;
  for (const auto& n : nodes) {
    if (n.max_sessions > 0 && n.running_sessions >= n.max_sessions) continue;
    if (!best || key(n) < key(*best)) best = &n;
  }
  return best;
}

Placement ClusterCoordinator::PlaceNew() {
  const auto nodes = LiveNodes();
  const NodeRow* target = LeastLoaded(nodes);
  if (!target) return Placement::Unavailable("every node of the fleet runs its maximum of sessions");
  if (target->node_id == options_.node_id) return Placement::Here(options_.node_id);
  std::lock_guard lock(mutex_);
  auto& placed = recent_placements_[target->node_id];
  placed.first = (Clock::now() - placed.second > Seconds(options_.lease_seconds)) ? 1 : placed.first + 1;
  placed.second = Clock::now();
  return Placement::Elsewhere(target->node_id, target->address);
}

Placement ClusterCoordinator::Claim(const std::string& session_id) {
  std::optional<LeaseRow> lease;
  std::vector<NodeRow> all;
  {
    std::lock_guard lock(db_mutex_);
    lease = repo_.Lease(session_id);
    all = repo_.Nodes(options_.lease_seconds);
  }
  if (lease && lease->node_id != options_.node_id && lease->expires_in > 0) {
    for (const auto& n : all) {
      if (n.node_id == lease->node_id) return Placement::Elsewhere(n.node_id, n.address);
    }
    return Placement::Unavailable("its node " + lease->node_id +
                                  " stopped answering; the session moves when its lease expires in " +
                                  std::to_string(static_cast<int>(lease->expires_in + 1)) + " s");
  }
  // Just handed over by rebalancing: its agent goes to the node taking it.
  if (const auto to = HandedTo(session_id)) return Placement::Elsewhere(to->node_id, to->address);
  std::optional<std::int64_t> epoch;
  {
    std::lock_guard lock(db_mutex_);
    epoch = repo_.TryAcquire(session_id, options_.node_id, options_.lease_seconds);
  }
  if (!epoch) return Placement::Unavailable("another node is taking the session over");
  Owned(session_id, *epoch);
  return Placement::Here(options_.node_id, *epoch);
}

std::optional<std::string> ClusterCoordinator::OwnerElsewhere(const std::string& session_id) {
  std::lock_guard lock(db_mutex_);
  const auto lease = repo_.Lease(session_id);
  if (!lease || lease->node_id == options_.node_id || lease->expires_in <= 0) return std::nullopt;
  for (const auto& n : repo_.Nodes(options_.lease_seconds)) {
    if (n.node_id == lease->node_id) return n.address;
  }
  return std::nullopt;
}

ClusterView ClusterCoordinator::View() {
  ClusterView view;
  view.node_id = options_.node_id;
  view.lease_seconds = options_.lease_seconds;
  std::lock_guard lock(db_mutex_);
  view.nodes = repo_.Nodes(1e12);
  view.leases = repo_.Leases();
  return view;
}

void ClusterCoordinator::Owned(const std::string& session_id, std::int64_t epoch) {
  std::lock_guard lock(mutex_);
  owned_[session_id] = epoch;
  released_.erase(session_id);
}

void ClusterCoordinator::Released(const std::string& session_id) {
  {
    std::lock_guard lock(mutex_);
    if (!owned_.erase(session_id)) return;
    released_.insert(session_id);
  }
  wake_.notify_all();
}

std::int64_t ClusterCoordinator::AcquireIn(Database& db, const std::string& session_id) {
  const auto epoch = ClusterRepository(db).TryAcquire(session_id, options_.node_id, options_.lease_seconds);
  if (!epoch) throw StorageError("session " + session_id + " is held by another node");
  Owned(session_id, *epoch);
  return *epoch;
}

void ClusterCoordinator::CheckLeaseIn(Database& db, const std::string& session_id, std::int64_t epoch) const {
  if (!ClusterRepository(db).HoldsLease(session_id, options_.node_id, epoch)) ThrowLeaseLost(session_id);
}

void ClusterCoordinator::InsertInputIn(SessionRepository& repo, const std::string& session_id, std::int64_t epoch,
                                       const InputRecord& input) const {
  if (!repo.InsertInputFenced(session_id, input, LeaseFence{options_.node_id, epoch})) ThrowLeaseLost(session_id);
}

}  // namespace pslam::server
