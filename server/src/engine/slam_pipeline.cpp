#include "engine/slam_pipeline.hpp"

#include "engine/localize_options.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace pslam::server {
namespace {

// Re-plan at least this often (input time), and whenever the robot is this close to its target.
constexpr double kReplanSeconds = 5.0;
constexpr double kTargetReachedMetres = 0.6;
// A robot with a path that has not moved this far for this long (input time) is stuck: its target
// is given up and another chosen. Long enough for turning on the spot and for an obstacle stop
// while a person passes.
constexpr double kProgressMetres = 0.3;
constexpr double kStuckSeconds = 30.0;

}  // namespace

LaserScan ToLaserScan(const InputRecord& input, const LaserGeometry& laser) {
  // Ingest admits only scans of the session's beam count, so a mismatch here is a stored input
  // damaged since: mapping it would silently shift every beam's angle.
  if (input.ranges.size() != static_cast<std::size_t>(laser.beams)) {
    throw std::runtime_error("input " + std::to_string(input.seq) + " is a scan of " +
                             std::to_string(input.ranges.size()) + " ranges, but the session's laser has " +
                             std::to_string(laser.beams) + " beams (a damaged stored input)");
  }
  LaserScan scan;
  scan.timestamp = input.t;
  scan.timestamp_text = input.stamp;
  scan.ranges = input.ranges;
  scan.angle_min = laser.angle_min;
  scan.angle_increment = laser.angle_increment;
  scan.max_range = laser.max_range;
  scan.min_range = laser.min_range;
  scan.sensor_offset = Pose2D(laser.offset_x, laser.offset_y, laser.offset_theta);
  scan.odometry = Pose2D(input.x, input.y, input.theta);
  return scan;
}

double MemoryLimitBytes(const SessionSettings& settings) {
  return static_cast<double>(settings.memory_limit_mb) * (1 << 20);
}

// The grids' tile tables are dense between the farthest tiles, and so are the rasters computed over
// a map's extent: each table slot costs a pointer per grid (two per particle) and, planned on, some
// 16 bytes for each of its cells (4 where only loop closure rasterises submaps). Bounding the table
// by the memory limit stops a far jump before it allocates, not after.
std::size_t MaxTileSlots(const SessionSettings& settings) {
  constexpr double kCellsPerTile = OccupancyGrid::kTileSize * OccupancyGrid::kTileSize;
  const double per_slot = 2.0 * settings.particles * sizeof(std::shared_ptr<OccupancyGrid::Tile>) +
                          kCellsPerTile * (settings.plan_targets ? 16.0 : 4.0);
  return static_cast<std::size_t>(std::max(64.0, MemoryLimitBytes(settings) / per_slot));
}

PSlamOptions ToPSlamOptions(const SessionSettings& settings) {
  PSlamOptions o;
  RbpfOptions& f = o.filter;
  f.particles = settings.particles;
  f.seed = settings.seed;
  f.threads = settings.threads;
  f.resolution = settings.resolution;
  f.linear_update = settings.linear_update;
  f.angular_update = settings.angular_update;
  f.resample_threshold = settings.resample_threshold;
  SetDegenerateRatio(f, settings.degenerate_ratio);
  SetMatchPrior(f, settings.odometry_prior);
  SetHitOffsets(f, settings.hit_offsets);
  f.grid.max_tile_slots = MaxTileSlots(settings);
  o.predict = settings.predict;
  o.heading_targets = !settings.plan_targets;
  // Predictor tunables arrive as a JSON object; unknown keys are errors, not silent defaults.
  const nlohmann::json p = nlohmann::json::parse(settings.predictor_json.empty() ? "{}" : settings.predictor_json);
  for (const auto& [key, value] : p.items()) {
    if (key == "similarity_threshold") o.predictor.similarity_threshold = value.get<double>();
    else if (key == "prediction_range") o.predictor.region_size_m = value.get<double>();
    else if (key == "recovery") f.recovery = value.get<bool>();
    else if (key == "hit_ratio_threshold") f.hit_ratio_threshold = value.get<double>();
    else throw std::invalid_argument("unknown predictor setting '" + key + "'");
  }
  if (const auto problem = ValidatePredictorOptions(o.predictor)) throw std::invalid_argument(*problem);
  return o;
}

namespace {

PSlamOptions WithLibrary(PSlamOptions options, const SessionSettings& settings,
                         const std::vector<SiteLibraryMap>& library) {
  if (settings.mode == "map" && options.predict) options.library = BuildMapLibrary(library, options.predictor);
  return options;
}

}  // namespace

SlamPipeline::SlamPipeline(const SessionSettings& settings, const LaserGeometry& laser, std::function<void()> plan_ready,
                           std::shared_ptr<const OccupancyGrid> fixed_map, std::vector<SiteLibraryMap> library)
    : settings_(settings),
      laser_(laser),
      library_(std::move(library)),
      divergence_(settings.particles) {
  if (settings_.mode == "localize" || settings_.mode == "extend") {
    if (!fixed_map) throw std::invalid_argument(settings_.mode + " mode needs the site's map");
    localization_ = std::make_unique<FixedMapLocalization>(std::move(fixed_map), ToMclOptions(settings_),
                                                           settings_.initial_pose);
  } else {
    slam_ = std::make_unique<PSlam>(WithLibrary(ToPSlamOptions(settings), settings, library_));
  }
  if (settings_.plan_targets) planner_ = std::make_unique<ExplorationPlanner>(std::move(plan_ready));
}

Pose2D SlamPipeline::CurrentPose() const {
  if (!localization_) return slam_->filter().best().pose;
  const auto& trajectory = localization_->trajectory();
  return trajectory.empty() ? Pose2D() : trajectory.back();
}

int SlamPipeline::particle_count() const {
  return static_cast<int>(localization_ ? localization_->particles().size() : slam_->filter().particles().size());
}

std::vector<Pose2D> SlamPipeline::Trajectory() const {
  if (localization_) return localization_->trajectory();
  std::vector<Pose2D> poses = localized_trajectory_;
  const std::vector<Pose2D> mapped = slam_->filter().Trajectory();
  poses.insert(poses.end(), mapped.begin(), mapped.end());
  return poses;
}

std::string SlamPipeline::phase() const {
  if (settings_.mode != "extend") return settings_.mode;
  return localization_ ? "extend_localize" : "extend_map";
}

void SlamPipeline::StartMapping(const Pose2D& pose) {
  PSlamOptions options = ToPSlamOptions(settings_);
  options.filter.prior_map = localization_->shared_map();
  options.filter.initial_pose = pose;
  slam_ = std::make_unique<PSlam>(options);
  // The scan that localized is the mapping filter's first: its pose comes from there.
  localized_trajectory_ = localization_->trajectory();
  localized_trajectory_.pop_back();
  localization_.reset();
}

void SlamPipeline::CheckMemory() const {
  const Rbpf& filter = slam_->filter();
  const auto mib = [](double bytes) { return std::to_string(static_cast<long long>(bytes / (1 << 20))) + " MiB"; };
  const std::string limit = std::to_string(settings_.memory_limit_mb) + " MiB";
  if (filter.RefusedMapWrites() > 0) {
    throw std::runtime_error("memory limit: the map would grow past what the session's " + limit +
                             " allow (the odometry jumped far away?)");
  }
  const double bytes = filter.MapBytes();
  if (bytes > MemoryLimitBytes(settings_)) {
    throw std::runtime_error("memory limit: the maps of " + std::to_string(filter.particles().size()) +
                             " particles take " + mib(bytes) + ", more than the session's " + limit);
  }
}

HypothesisRecord SlamPipeline::ToRecord(const Hypothesis& h) const {
  HypothesisRecord r;
  r.id = h.id;
  r.time = h.time;
  r.target_cell = {h.target_cell.x(), h.target_cell.y()};
  r.reference_cell = {h.reference_cell.x(), h.reference_cell.y()};
  for (const SiteLibraryMap& m : library_) {
    if (h.reference_map == LibraryMapId(m.site, m.version)) r.reference_map = SiteMapRef{m.site, m.version};
  }
  r.theta = h.theta;
  r.translation_x = h.translation.x();
  r.translation_y = h.translation.y();
  r.psi = h.psi;
  r.area = h.area_m2;
  r.cells.reserve(h.cells.size());
  for (const HypothesisCell& c : h.cells) r.cells.push_back({c.cell.x(), c.cell.y(), c.occupied ? 0.95f : 0.12f});
  r.status = StatusName(h.status);
  r.hit_ratio = std::isnan(h.hit_ratio) ? 0.0 : h.hit_ratio;
  r.psi_observed = std::isnan(h.psi_observed) ? 0.0 : h.psi_observed;
  return r;
}

PipelineStep SlamPipeline::Add(const InputRecord& input) {
  PipelineStep step;
  // Odometry messages are stored for replay; the filter takes the odometry that each scan carries
  // (interpolated by the agent to the scan time).
  if (input.kind != InputKind::kScan) return step;
  step.scan = std::make_shared<const LaserScan>(ToLaserScan(input, laser_));
  if (localization_) {
    step.filter = localization_->Add(*step.scan);
    if (settings_.mode == "extend" && localization_->ready_to_map()) {
      StartMapping(step.filter.pose);
    } else {
      if (planner_) {
        WatchProgress(input.t, step);
        step.target = TakePlan();
        LookAroundWhileSearching(step);
        MaybeRequestPlan(input.t);
      }
      return step;
    }
  }
  const std::size_t known = slam_->hypotheses().size();
  PSlamStep s = slam_->AddScan(*step.scan);
  CheckMemory();
  step.filter = s.filter;
  step.tracking_changed = divergence_.Add(s.filter, *step.scan);
  // New hypotheses (possibly taken from the predictor during this scan) and changed ones.
  for (std::size_t i = known; i < slam_->hypotheses().size(); ++i) s.changed_hypotheses.push_back(slam_->hypotheses()[i].id);
  for (const int id : s.changed_hypotheses) {
    for (const Hypothesis& h : slam_->hypotheses()) {
      if (h.id != id) continue;
      HypothesisRecord record = ToRecord(h);
      const auto [it, inserted] = record_index_.try_emplace(id, hypotheses_.size());
      if (inserted) hypotheses_.push_back(record);
      else hypotheses_[it->second] = record;
      step.hypotheses_changed.push_back(std::move(record));
    }
  }
  if (planner_) {
    WatchProgress(input.t, step);
    step.target = TakePlan();
    // Planned on input time, not on filter updates: a robot that reached its target stands still,
    // and would never be given the next one.
    MaybeRequestPlan(input.t);
  }
  return step;
}

void SlamPipeline::LookAroundWhileSearching(PipelineStep& step) {
  // A robot that sees 180 degrees ahead misses what is behind it, often what tells its place from
  // a look-alike one (a corridor's end): turning once in place lets the search see all around.
  const bool searching = !localization_->status().place.empty();
  if (!searching) {
    looked_around_ = false;  // the next search (after a kidnapping) looks around again
    return;
  }
  if (looked_around_) return;
  looked_around_ = true;
  const Pose2D pose = CurrentPose();
  ExplorationTarget look = step.target ? *step.target : target_.value_or(ExplorationTarget{pose.x, pose.y, {}, pose.x, pose.y, pose.theta});
  look.turn = 2.0 * std::numbers::pi;
  target_ = look;
  step.target = look;
}

void SlamPipeline::MaybeRequestPlan(double time) {
  const Pose2D pose = CurrentPose();
  const bool near_target = target_ && std::hypot(target_->x - pose.x, target_->y - pose.y) < kTargetReachedMetres;
  if (!near_target && time - last_plan_time_ < kReplanSeconds) return;
  if (planner_->busy()) return;  // asked again at the next input
  // Localize mode plans on the fixed map, with no predictions.
  PlanRequest request{map(), localization_ ? PredictionCoverage(map().resolution()) : slam_->coverage(), pose,
                      settings_.predict && !localization_, time, verify_predicted_, blacklist_};
  if (planner_->Request(std::move(request))) last_plan_time_ = time;
}

void SlamPipeline::WatchProgress(double time, PipelineStep& step) {
  const Pose2D pose = CurrentPose();
  const bool driving = target_ && !target_->path.empty();
  if (!driving || !progress_anchor_ || std::hypot(pose.x - progress_anchor_->x, pose.y - progress_anchor_->y) > kProgressMetres) {
    progress_anchor_ = pose;
    progress_anchor_time_ = time;
    return;
  }
  if (time - progress_anchor_time_ < kStuckSeconds) return;
  step.stuck = StuckReport{time, pose.x, pose.y, target_->x, target_->y, time - progress_anchor_time_};
  blacklist_.emplace_back(target_->x, target_->y);
  target_.reset();
  progress_anchor_.reset();
  last_plan_time_ = -1e300;  // choose another target at once
}

void SlamPipeline::UpdateExploration(const PlanResult& plan) {
  ExplorationStatus next;
  next.mapped_m2 = plan.mapped_m2;
  next.predicted_m2 = plan.predicted_m2;
  next.predicted_frontiers = plan.skipped;
  next.t = plan.time;
  const auto count = [](int n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); };
  if (plan.target) {
    // Verifying opens frontiers of its own, which skip mode then takes: still verifying.
    next.state = plan.verifying || exploration_.state == "verifying" ? "verifying" : "exploring";
    if (plan.verifying) next.reason = "only frontiers that predictions cover are left: visiting them to verify the predictions";
  } else if (plan.start_blocked) {
    next.state = "blocked";
    next.reason = "the robot cannot leave its position on the map";
  } else if (plan.skipped > 0) {
    next.state = "waiting_for_verification";
    next.reason = count(plan.skipped, "frontier") + " left that predictions cover; verifying them is off";
  } else {
    next.state = "complete";
    if (plan.unreachable > 0 || plan.blacklisted > 0) {
      next.reason = count(plan.unreachable, "frontier") + " no path reaches, " + count(plan.blacklisted, "target") +
                    " given up";
    }
  }
  // An event per new state; the reason's counts change at every plan and are in the statistics.
  if (next.state != exploration_.state) exploration_changed_ = true;
  exploration_ = std::move(next);
}

std::optional<ExplorationTarget> SlamPipeline::TakePlan() {
  if (!planner_) return std::nullopt;
  std::optional<PlanResult> plan = planner_->TakeResult();
  if (!plan) return std::nullopt;
  if (!plan->error.empty()) throw std::runtime_error("exploration planning failed: " + plan->error);
  UpdateExploration(*plan);
  frontiers_ = std::move(plan->frontiers);
  const Pose2D& pose = plan->pose;
  if (!plan->target) {
    // Exploration is done (or blocked): tell the robot to stop by sending an empty path once.
    if (exploration_done_) return std::nullopt;
    exploration_done_ = true;
    target_ = ExplorationTarget{pose.x, pose.y, {}, pose.x, pose.y, pose.theta};
    return target_;
  }
  exploration_done_ = false;
  if (!localization_) slam_->SetTarget(plan->target->cell, plan->time);
  ExplorationTarget t;
  t.x = plan->target->position.x();
  t.y = plan->target->position.y();
  for (const Eigen::Vector2d& p : plan->target->path) t.path.push_back({p.x(), p.y()});
  t.pose_x = pose.x;
  t.pose_y = pose.y;
  t.pose_theta = pose.theta;
  target_ = t;
  return target_;
}

std::vector<Pose2D> SlamPipeline::ParticlePoses() const {
  if (localization_) return localization_->particles();
  std::vector<Pose2D> poses;
  poses.reserve(slam_->filter().particles().size());
  for (const Particle& p : slam_->filter().particles()) poses.push_back(p.pose);
  return poses;
}

}  // namespace pslam::server
