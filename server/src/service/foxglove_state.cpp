#include "service/foxglove_state.hpp"

#include <algorithm>

namespace pslam::server {
namespace {

bool Same(const Pose2D& a, const Pose2D& b) { return a.x == b.x && a.y == b.y && a.theta == b.theta; }

bool SamePoses(const std::vector<Pose2D>& a, const std::vector<Pose2D>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), Same);
}

bool SameTarget(const std::optional<ExplorationTarget>& a, const std::optional<ExplorationTarget>& b) {
  if (!a || !b) return !a && !b;
  return a->x == b->x && a->y == b->y && a->path == b->path;
}

}  // namespace

FoxgloveState::Clock::duration FoxgloveState::Period(FoxgloveTopic topic) {
  using std::chrono::milliseconds;
  switch (topic) {
    case FoxgloveTopic::kMap:  // the whole map each time (docs/benchmarks.md)
    case FoxgloveTopic::kTrajectory:
    case FoxgloveTopic::kPrediction:
      return milliseconds(2000);
    case FoxgloveTopic::kParticles:
      return milliseconds(500);
    default:
      return Clock::duration::zero();  // every tick that changed it (ticks are at most 10 per second)
  }
}

void FoxgloveState::Changed(FoxgloveTopic t, std::uint64_t ns) {
  Slot& s = SlotOf(t);
  s.has_data = s.stale = s.unsent = true;
  s.ns = ns;
}

std::vector<FoxgloveMessage> FoxgloveState::Apply(const LiveFrame& f, std::uint64_t ns, Clock::time_point now,
                                                  const Listening& listening) {
  if (f.map && (!f.tiles.empty() || !map_)) {
    map_ = f.map;
    Changed(FoxgloveTopic::kMap, ns);
  }
  if (f.pose && (!pose_ || !Same(*f.pose, *pose_))) {
    pose_ = f.pose;
    Changed(FoxgloveTopic::kRobot, ns);
    Changed(FoxgloveTopic::kTransform, ns);
  }
  if (f.scan && f.pose && f.scan_seq != scan_seq_) {
    scan_ = f.scan;
    scan_pose_ = *f.pose;
    scan_seq_ = f.scan_seq;
    Changed(FoxgloveTopic::kScan, ns);
  }
  if (!f.trajectory.empty()) {
    // Increments are contiguous; a restarted engine starts again at 0 and replaces the history.
    const auto first = static_cast<std::size_t>(std::max<std::int64_t>(f.trajectory_first_index, 0));
    if (first < trajectory_.size()) trajectory_.resize(first);
    for (const TrajectoryRow& r : f.trajectory) trajectory_.emplace_back(r.x, r.y, r.theta);
    Changed(FoxgloveTopic::kTrajectory, ns);
  }
  if (!f.particles.empty() && !SamePoses(f.particles, particles_)) {
    particles_ = f.particles;
    Changed(FoxgloveTopic::kParticles, ns);
  }
  resolution_ = f.resolution;
  bool predictions_changed = false;
  for (const HypothesisRecord& h : f.hypotheses_changed) {
    // Only pending predictions are drawn: the others are mapped by now, or were never checked.
    predictions_changed = predictions_changed || h.status == "pending" || pending_.count(h.id);
    if (h.status == "pending") {
      pending_[h.id] = h;
    } else {
      pending_.erase(h.id);
    }
  }
  for (const std::int64_t id : f.hypotheses_removed) predictions_changed = pending_.erase(id) > 0 || predictions_changed;
  if (predictions_changed || !SlotOf(FoxgloveTopic::kPrediction).has_data) Changed(FoxgloveTopic::kPrediction, ns);
  stats_ = f.stats;
  if (f.send_stats) Changed(FoxgloveTopic::kStats, ns);
  if (f.frontiers != frontiers_ || !SameTarget(f.target, target_) || !SlotOf(FoxgloveTopic::kExploration).has_data) {
    frontiers_ = f.frontiers;
    target_ = f.target;
    Changed(FoxgloveTopic::kExploration, ns);
  }
  return Due(now, listening);
}

std::vector<FoxgloveMessage> FoxgloveState::Flush(Clock::time_point now, const Listening& listening) {
  return Due(now, listening);
}

std::vector<FoxgloveMessage> FoxgloveState::Due(Clock::time_point now, const Listening& listening) {
  std::vector<FoxgloveMessage> out;
  for (const FoxgloveTopic t : kFoxgloveTopics) {
    Slot& s = SlotOf(t);
    if (!s.unsent || now - s.last_sent < Period(t)) continue;
    s.unsent = false;
    s.last_sent = now;
    if (!listening[static_cast<std::size_t>(t)]) continue;  // a later subscriber encodes the value then
    if (auto m = Latest(t)) out.push_back(std::move(*m));
  }
  return out;
}

std::optional<FoxgloveState::Clock::time_point> FoxgloveState::NextDue() const {
  std::optional<Clock::time_point> next;
  for (const FoxgloveTopic t : kFoxgloveTopics) {
    const Slot& s = slots_[static_cast<std::size_t>(t)];
    if (!s.unsent) continue;
    const Clock::time_point due = s.last_sent + Period(t);
    if (!next || due < *next) next = due;
  }
  return next;
}

std::optional<FoxgloveMessage> FoxgloveState::Latest(FoxgloveTopic t) {
  Slot& s = SlotOf(t);
  if (!s.has_data) return std::nullopt;
  if (s.stale) {
    s.cached = Encode(t);
    s.stale = false;
  }
  return FoxgloveMessage{t, s.ns, s.cached};
}

Bytes FoxgloveState::Encode(FoxgloveTopic t) const {
  const std::uint64_t ns = slots_[static_cast<std::size_t>(t)].ns;
  switch (t) {
    case FoxgloveTopic::kMap:
      return MakeBytes(map_ ? GridPayload(*map_, ns) : GridPayload(OccupancyGrid(), ns));
    case FoxgloveTopic::kRobot:
      return MakeBytes(PoseInFramePayload(pose_.value_or(Pose2D()), ns));
    case FoxgloveTopic::kTransform:
      return MakeBytes(TransformPayload(session_id_, pose_.value_or(Pose2D()), ns));
    case FoxgloveTopic::kScan:
      return MakeBytes(scan_ ? LaserScanPayload(*scan_, scan_pose_, ns) : LaserScanPayload(LaserScan(), Pose2D(), ns));
    case FoxgloveTopic::kTrajectory:
      return MakeBytes(PosesInFramePayload(trajectory_, ns, kFoxgloveMaxPoses));
    case FoxgloveTopic::kParticles:
      return MakeBytes(PosesInFramePayload(particles_, ns, particles_.size()));
    case FoxgloveTopic::kStats:
      return MakeBytes(StatsPayload(stats_));
    case FoxgloveTopic::kExploration:
      return MakeBytes(ExplorationPayload(frontiers_, target_, ns));
    case FoxgloveTopic::kPrediction: {
      std::vector<const HypothesisRecord*> pending;
      for (const auto& [id, h] : pending_) pending.push_back(&h);
      return MakeBytes(PredictionPayload(pending, resolution_, ns));
    }
  }
  return MakeBytes("{}");
}

}  // namespace pslam::server
