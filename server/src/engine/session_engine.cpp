#include "engine/session_engine.hpp"

#include <algorithm>
#include <exception>
#include <utility>

#include "engine/tile_codec.hpp"

namespace pslam::server {
namespace {
constexpr double kRateWindowSeconds = 5.0;
constexpr std::size_t kTimingWindow = 200;
constexpr std::size_t kMaxLiveParticles = 2000;  // a viewer needs the cloud's shape, not every particle
}  // namespace

SteadyTime::duration SessionEngine::StatsPeriod() const {
  return std::chrono::duration_cast<SteadyTime::duration>(std::chrono::duration<double>(timing_.stats_period_seconds));
}

SessionEngine::SessionEngine(std::string session_id, SessionSettings settings, LaserGeometry laser,
                             EngineTiming timing, EngineSinks sinks, SiteMaps site_maps)
    : session_id_(std::move(session_id)),
      settings_(std::move(settings)),
      laser_(laser),
      timing_(timing),
      sinks_(std::move(sinks)),
      site_maps_(std::move(site_maps)) {}

SessionEngine::~SessionEngine() {
  Join(StopMode::kAbort);
  pipeline_.reset();  // joins the planner, whose callback uses mutex_ and wake_
}

void SessionEngine::Start(BacklogReader backlog, std::int64_t backlog_until, AppliedPoses applied_poses) {
  rebuilding_ = backlog_until > 0;
  replayed_poses_ = std::move(applied_poses);
  thread_ = std::thread([this, backlog = std::move(backlog), backlog_until]() mutable {
    Loop(std::move(backlog), backlog_until);
  });
}

void SessionEngine::Push(InputRecord input, SteadyTime received) {
  {
    std::lock_guard lock(mutex_);
    if (stop_ != StopMode::kNone || failed_) return;
    queue_.push_back({std::move(input), received});
  }
  wake_.notify_one();
}

void SessionEngine::WaitForRoom(std::size_t max_queued) {
  std::unique_lock lock(mutex_);
  room_.wait(lock, [&] { return queue_.size() < max_queued || stop_ != StopMode::kNone || failed_; });
}

void SessionEngine::SetInitialPose(const InitialPose& pose) {
  std::lock_guard lock(mutex_);
  pending_pose_ = pose;
}

void SessionEngine::Finish() { Join(StopMode::kFinish); }
void SessionEngine::Stop() { Join(StopMode::kStop); }
void SessionEngine::Abort() { Join(StopMode::kAbort); }

void SessionEngine::Join(StopMode mode) {
  {
    std::lock_guard lock(mutex_);
    // A stronger request overrides a weaker one (abort > stop > finish), never the reverse.
    if (static_cast<int>(mode) > static_cast<int>(stop_)) stop_ = mode;
  }
  wake_.notify_all();
  room_.notify_all();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

std::size_t SessionEngine::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

EngineStats SessionEngine::stats() const {
  std::lock_guard lock(mutex_);
  EngineStats s = stats_;
  s.queued = queue_.size();
  s.rebuilding = rebuilding_;
  return s;
}

std::shared_ptr<const LiveFrame> SessionEngine::latest_frame() const {
  std::lock_guard lock(mutex_);
  return latest_frame_;
}

void SessionEngine::Loop(BacklogReader backlog, std::int64_t backlog_until) {
  try {
    pipeline_ = std::make_unique<SlamPipeline>(settings_, laser_, [this] {
      {
        std::lock_guard lock(mutex_);
        plan_ready_ = true;
      }
      wake_.notify_one();
    }, std::move(site_maps_.fixed_map), std::move(site_maps_.library));
    last_checkpoint_ = SteadyNow();
    live_tokens_.emplace(1.0 / timing_.live_period_seconds, timing_.live_burst, last_checkpoint_);
    // Rebuild: the stored inputs of a resumed session, straight from the database.
    std::int64_t after = 0;
    bool more = backlog_until > 0;
    while (more) {
      {
        std::lock_guard lock(mutex_);
        if (stop_ == StopMode::kAbort || stop_ == StopMode::kStop) break;
      }
      const std::vector<InputRecord> chunk = backlog(after);
      more = !chunk.empty();
      for (const InputRecord& input : chunk) {
        if (input.seq > backlog_until) {
          more = false;
          break;
        }
        Process(input, std::nullopt);
        after = input.seq;
      }
      if (after >= backlog_until) more = false;
    }
    rebuilding_ = false;
    if (backlog_until > 0 && after >= backlog_until && sinks_.rebuilt) sinks_.rebuilt();

    for (;;) {
      Queued next;
      {
        std::unique_lock lock(mutex_);
        if (queue_.empty() && stop_ == StopMode::kNone) {
          // Idle: wake for the next input, a finished plan, or to publish what the last inputs changed.
          const auto woken = [&] { return !queue_.empty() || stop_ != StopMode::kNone || plan_ready_; };
          const SteadyTime now = SteadyNow();
          if (live_dirty_) {
            wake_.wait_until(lock, live_tokens_->NextToken(now), woken);
          } else if (stats_pending_) {  // the last stats held back by the stats period
            wake_.wait_until(lock, std::max(live_tokens_->NextToken(now), last_stats_sent_ + StatsPeriod()), woken);
          } else {
            wake_.wait(lock, woken);
          }
        }
        if (stop_ == StopMode::kAbort || stop_ == StopMode::kStop) break;
        const bool plan_ready = std::exchange(plan_ready_, false);  // an input takes it too
        if (queue_.empty()) {
          if (stop_ == StopMode::kFinish) break;
          lock.unlock();
          if (plan_ready) TakePlan();
          const SteadyTime now = SteadyNow();
          if ((live_dirty_ || StatsDue(now)) && live_tokens_->TryTake(now)) PublishLive();
          continue;
        }
        next = std::move(queue_.front());
        queue_.pop_front();
      }
      room_.notify_all();
      Process(next.input, next.received);
    }
    StopMode mode;
    {
      std::lock_guard lock(mutex_);
      mode = stop_;
    }
    if (mode != StopMode::kAbort) {
      PublishLive(/*final_tick=*/true);
      WriteCheckpoint(/*final_checkpoint=*/true);
      if (mode == StopMode::kFinish && sinks_.finished) sinks_.finished();
    }
  } catch (const std::exception& e) {
    failed_ = true;
    // Release the maps now: the session is over, and after an allocation failure the process
    // needs the memory back before anything else.
    pipeline_.reset();
    {
      std::lock_guard lock(mutex_);
      latest_frame_.reset();
      queue_.clear();
    }
    room_.notify_all();
    if (sinks_.failed) sinks_.failed(e.what());
  }
  exited_ = true;
}

// A loop closure corrected the past: viewers and storage get the whole corrected trajectory.
void SessionEngine::ReplaceTrajectory() {
  const std::vector<Pose2D> corrected = pipeline_->Trajectory();
  for (std::size_t i = 0; i < online_.size() && i < corrected.size(); ++i) {
    online_[i].x = corrected[i].x;
    online_[i].y = corrected[i].y;
    online_[i].theta = corrected[i].theta;
  }
  live_trajectory_sent_ = 0;
  stored_trajectory_replaced_ = true;
}

void SessionEngine::Process(const InputRecord& input, std::optional<SteadyTime> received) {
  if (input.seq <= processed_seq_.load()) return;  // already in the filter
  const SteadyTime start = SteadyNow();
  pipeline_->SetVerifyPredicted(verify_predicted_);
  if (pipeline_->localizing()) {
    std::optional<InitialPose> pose;
    if (const auto stored = replayed_poses_.find(input.seq); stored != replayed_poses_.end()) {
      pose = stored->second;  // set before a restart: the rebuild applies it where it was applied then
      replayed_poses_.erase(stored);
    } else {
      {
        std::lock_guard lock(mutex_);
        pose = std::exchange(pending_pose_, std::nullopt);
      }
      if (pose && sinks_.pose_applied) sinks_.pose_applied(input.seq, *pose);
    }
    if (pose) pipeline_->SetPose(*pose);
  }
  PipelineStep step = pipeline_->Add(input);
  if (step.scan) last_scan_ = step.scan;
  const double step_ms = SecondsSince(start) * 1e3;
  if (step.scan) {
    online_.push_back({static_cast<std::int64_t>(online_.size()), input.seq, input.t, input.stamp, step.filter.pose.x,
                       step.filter.pose.y, step.filter.pose.theta});
    if (step.filter.loop_corrected) ReplaceTrajectory();
    recent_scans_.push_back(SteadyNow());
    RecordTiming(received ? SecondsSince(*received) * 1e3 : -1.0, step_ms);
  }
  for (HypothesisRecord& h : step.hypotheses_changed) {
    live_hypotheses_.push_back(h);
    stored_hypotheses_.push_back(std::move(h));
  }
  for (std::int64_t id : step.hypotheses_removed) live_removed_.push_back(id);
  if (step.stuck && sinks_.stuck && !rebuilding_) sinks_.stuck(*step.stuck);
  if (step.target) SendTarget(*step.target);
  ReportExploration();
  if (step.tracking_changed) ReportTracking(input);
  processed_seq_ = input.seq;
  live_dirty_ = stored_dirty_ = true;
  if (sinks_.progress) sinks_.progress(input.seq);

  const SteadyTime now = SteadyNow();
  if (live_tokens_->TryTake(now)) PublishLive();
  if (std::chrono::duration<double>(now - last_checkpoint_).count() >= timing_.checkpoint_period_seconds) {
    WriteCheckpoint(false);
  }
}

void SessionEngine::TakePlan() {
  const auto frontiers_before = pipeline_->frontiers();
  const std::optional<ExplorationTarget> target = pipeline_->TakePlan();
  ReportExploration();
  // A plan that changes nothing the viewers see is no reason for a live tick.
  if (pipeline_->frontiers() != frontiers_before) live_dirty_ = true;
  if (!target) return;
  live_dirty_ = true;
  SendTarget(*target);
}

void SessionEngine::SendTarget(const ExplorationTarget& target) {
  live_target_ = target;
  if (sinks_.target && !rebuilding_) sinks_.target(target);
}

void SessionEngine::ReportExploration() {
  if (!pipeline_->TakeExplorationChange()) return;
  last_stats_sent_ = SteadyTime{};  // viewers see it at the next live tick
  live_dirty_ = true;
  if (sinks_.exploration && !rebuilding_) sinks_.exploration(pipeline_->exploration());
}

void SessionEngine::ReportTracking(const InputRecord& input) {
  // An operator should see this at the next live tick, not only after the stats period.
  last_stats_sent_ = SteadyTime{};
  if (!sinks_.tracking || rebuilding_) return;
  const DivergenceMonitor& monitor = pipeline_->divergence();
  sinks_.tracking({monitor.changed_at_scan(), input.seq, input.t, TrackingStateName(monitor.state()), monitor.reason()});
}

void SessionEngine::RecordTiming(double latency_ms, double step_ms) {
  recent_timing_.emplace_back(latency_ms, step_ms);
  if (recent_timing_.size() > kTimingWindow) recent_timing_.pop_front();
}

EngineStats SessionEngine::CurrentStats() const {
  EngineStats s;
  s.processed_seq = processed_seq_.load();
  const RbpfStats& f = pipeline_->filter_stats();
  s.scans = f.scans;
  s.updates = f.updates;
  s.resamplings = f.resamplings;
  s.neff = f.neff;
  s.particles = pipeline_->started() ? pipeline_->particle_count() : settings_.particles;
  s.tracking = TrackingStateName(pipeline_->divergence().state());
  s.tracking_reason = pipeline_->divergence().reason();
  s.updates_using_predictions = f.updates_using_predictions;
  const ExplorationStatus& e = pipeline_->exploration();
  s.exploration = e.state;
  s.exploration_reason = e.reason;
  s.mapped_m2 = e.mapped_m2;
  s.predicted_m2 = e.predicted_m2;
  s.predicted_frontiers = e.predicted_frontiers;
  s.mode = pipeline_->phase();
  if (pipeline_->localizing()) s.localization = pipeline_->localization();
  const PSlamStats p = pipeline_->pslam_stats();
  s.targets = p.targets;
  s.predictions_made = p.predictions_made;
  s.hypotheses = p.hypotheses;
  s.prediction_ms_mean = p.outcomes.predictions ? p.outcomes.total_ms / static_cast<double>(p.outcomes.predictions) : 0.0;
  s.prediction_ms_max = p.max_prediction_ms;
  const SteadyTime now = SteadyNow();
  std::size_t in_window = 0;
  for (auto it = recent_scans_.rbegin(); it != recent_scans_.rend(); ++it) {
    if (std::chrono::duration<double>(now - *it).count() > kRateWindowSeconds) break;
    ++in_window;
  }
  if (in_window > 1) {
    const double span = std::chrono::duration<double>(now - recent_scans_[recent_scans_.size() - in_window]).count();
    s.scan_rate_hz = span > 0 ? static_cast<double>(in_window) / std::max(span, 1e-3) : 0.0;
  }
  double latency_sum = 0.0, step_sum = 0.0;
  std::size_t latency_n = 0;
  for (const auto& [latency, step] : recent_timing_) {
    step_sum += step;
    if (latency < 0) continue;
    latency_sum += latency;
    ++latency_n;
    s.latency_ms_max = std::max(s.latency_ms_max, latency);
  }
  if (latency_n > 0) s.latency_ms_mean = latency_sum / static_cast<double>(latency_n);
  if (!recent_timing_.empty()) s.step_ms_mean = step_sum / static_cast<double>(recent_timing_.size());
  s.rebuilding = rebuilding_;
  return s;
}

bool SessionEngine::StatsDue(SteadyTime now) const {
  return stats_pending_ && now - last_stats_sent_ >= StatsPeriod();
}

void SessionEngine::PublishLive(bool final_tick) {
  const SteadyTime now = SteadyNow();
  while (recent_scans_.size() > 1 &&
         std::chrono::duration<double>(now - recent_scans_.front()).count() > kRateWindowSeconds) {
    recent_scans_.pop_front();
  }
  auto frame = std::make_shared<LiveFrame>();
  frame->resolution = settings_.resolution;
  frame->stats = CurrentStats();
  frame->send_stats = final_tick || now - last_stats_sent_ >= StatsPeriod();
  if (frame->send_stats) last_stats_sent_ = now;
  stats_pending_ = !frame->send_stats;
  if (pipeline_->started()) {
    frame->map = std::make_shared<const OccupancyGrid>(pipeline_->map());
    for (const Eigen::Vector2i& t : live_tiles_.Changed(*frame->map)) {
      const OccupancyGrid::Tile* tile = frame->map->TileAt(t.x(), t.y());
      frame->tiles.push_back({t.x(), t.y(), tile ? tile->revision : 0,
                              std::make_shared<const std::vector<std::uint8_t>>(EncodeLiveTile(tile))});
    }
    frame->particles = pipeline_->ParticlePoses();
    frame->weights = pipeline_->Weights();
    if (frame->particles.size() > kMaxLiveParticles) {
      frame->particles.resize(kMaxLiveParticles);
      frame->weights.resize(kMaxLiveParticles);
    }
  }
  if (!online_.empty()) {
    const TrajectoryRow& last = online_.back();
    frame->pose = Pose2D(last.x, last.y, last.theta);
    frame->scan = last_scan_;
    frame->scan_seq = last.seq;
  }
  frame->trajectory_first_index = static_cast<std::int64_t>(live_trajectory_sent_);
  frame->trajectory.assign(online_.begin() + static_cast<std::ptrdiff_t>(live_trajectory_sent_), online_.end());
  live_trajectory_sent_ = online_.size();
  frame->hypotheses_changed = std::move(live_hypotheses_);
  live_hypotheses_.clear();
  frame->hypotheses_removed = std::move(live_removed_);
  live_removed_.clear();
  frame->frontiers = pipeline_->frontiers();
  frame->target = live_target_;
  live_dirty_ = false;
  {
    std::lock_guard lock(mutex_);
    stats_ = frame->stats;
    latest_frame_ = frame;
  }
  if (sinks_.live) sinks_.live(frame);
}

void SessionEngine::WriteCheckpoint(bool final_checkpoint) {
  last_checkpoint_ = SteadyNow();
  if (!stored_dirty_ && !final_checkpoint) return;
  stored_dirty_ = false;
  Checkpoint c;
  c.session_id = session_id_;
  c.processed_seq = processed_seq_.load();
  c.resolution = settings_.resolution;
  c.scans = static_cast<std::int64_t>(online_.size());
  if (pipeline_->started()) {
    const OccupancyGrid map = pipeline_->map();  // a copy: the tracker keeps it
    for (const Eigen::Vector2i& t : stored_tiles_.Changed(map)) {
      const OccupancyGrid::Tile* tile = map.TileAt(t.x(), t.y());
      c.tiles.push_back({t.x(), t.y(), OccupancyGrid::kTileSize, tile ? static_cast<std::int64_t>(tile->revision) : 0,
                         EncodeStoredTile(tile)});
    }
  }
  if (final_checkpoint && pipeline_->started()) {
    // The best particle's trajectory, corrected by everything the filter learned since.
    const std::vector<Pose2D> smoothed = pipeline_->Trajectory();
    c.replace_trajectory = true;
    c.trajectory = online_;
    for (std::size_t i = 0; i < c.trajectory.size() && i < smoothed.size(); ++i) {
      c.trajectory[i].x = smoothed[i].x;
      c.trajectory[i].y = smoothed[i].y;
      c.trajectory[i].theta = smoothed[i].theta;
    }
  } else if (stored_trajectory_replaced_) {
    c.replace_trajectory = true;
    c.trajectory = online_;
  } else {
    c.trajectory.assign(online_.begin() + static_cast<std::ptrdiff_t>(stored_trajectory_sent_), online_.end());
  }
  stored_trajectory_replaced_ = false;
  stored_trajectory_sent_ = online_.size();
  c.stats = CurrentStats();
  c.hypotheses = std::move(stored_hypotheses_);
  stored_hypotheses_.clear();
  if (sinks_.checkpoint) sinks_.checkpoint(std::move(c));
}

}  // namespace pslam::server
