#include "pslam/experiment/exploration_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <variant>

namespace pslam {
namespace {

PSlamOptions SlamOptionsFor(const ExplorationOptions& exploration, const Pose2D& start) {
  PSlamOptions options = exploration.slam;
  options.filter.initial_pose = start;
  options.heading_targets = false;  // the explorer sets the targets
  // The predictor sees the map the explorer plans on, so that the edge of what is predicted,
  // where the targets lie, has surroundings to predict from.
  options.predict_on_merged_map =
      exploration.explore.mode == ExploreMode::kSkipPredicted && exploration.plan_on_merged_map;
  return options;
}

}  // namespace

ExplorationOptions DefaultExplorationOptions() {
  ExplorationOptions options;
  options.slam.filter.points.max_usable_range = options.simulator.laser.max_range;
  // Just short of max_range: the last few centimetres of a miss are where a wall would start.
  options.slam.filter.points.no_return_free_range = options.simulator.laser.max_range - 0.1;
  // The 8 m laser sees neither end of a long corridor: without the degeneracy guard the map slid
  // along corridors in most maze runs (mean position error 0.3-1.5 m in 8 of 12, against 1 of 12
  // with it). On the Intel log, whose corridors the laser spans, it made matters worse (6 of 10
  // seeds within 3 cm against 8 of 10), so it is not the filter's default.
  SetDegenerateRatio(options.slam.filter, 0.15);
  // What the guard hands to odometry carries the simulated wheels' calibration error (1 % of
  // distance): learn it where the scan pins the pose down (docs/loop-closure.md).
  options.slam.filter.odometry_calibration.enabled = true;
  // The simulated wheels err by about 1 % of distance: trust them where the scan's cost is flat.
  // Without this prior the matches slid a decimetre at a time in rooms seen by few scans yet, and
  // the maps doubled walls (office mean position error 0.49-0.77 m, map Psi 0.14-0.32; with it
  // 0.09 m and 0.76-0.78, seeds 1-4, docs/loop-closure.md). Real logs' odometry is far worse:
  // this weight took ACES from 0.038 to 0.17 m RPE, so the filter's own default is none.
  // The heading is held too, more lightly: stepping through a door into a room mapped only
  // through it, the matches turned the robot by 1.5 degrees within a second, and with no loop to
  // close the rest of a long loop-free building was mapped bent (generated school 25: 2.1 and
  // 3.6 m off on average at run seeds 1 and 2).
  // At 40 the wheels' early turn error held instead (docs/loop-closure.md).
  SetMatchPrior(options.slam.filter, 30.0, 10.0);
  // The simulated walls lie on the edges of the map's cells, where matching on cell centres both
  // turns the scan (a wall pulls endpoints half a cell into itself) and holds the map on the true
  // grid. With hit offsets the turn is gone but so is the hold: the office drifted twice as far
  // (docs/loop-closure.md). Real walls lie anywhere in a cell, so the filter's default is on.
  SetHitOffsets(options.slam.filter, false);
  // Skip-predicted runs stopped with a wing unexplored when a predicted wall stood where it opens.
  options.explore.way_in_cost_factor = 3.0;
  return options;
}

double ExplorationTimeBudget(const World& world) {
  const double free_m2 = static_cast<double>(world.Count(WorldCell::kFree)) * world.resolution() * world.resolution();
  return std::max(kMinExplorationTimeS, kExplorationSecondsPerFreeM2 * free_m2);
}

const char* ExplorationStateName(ExplorationState state) {
  switch (state) {
    case ExplorationState::kRunning: return "running";
    case ExplorationState::kExplored: return "explored";
    case ExplorationState::kTimeLimit: return "time limit";
    case ExplorationState::kStuck: return "stuck";
  }
  return "unknown";
}

ExplorationRun::ExplorationRun(World world, const Pose2D& start, const ExplorationOptions& options)
    : options_(options),
      simulator_(std::move(world), start, options.simulator),
      slam_(SlamOptionsFor(options, start)),
      follower_(options.follower),
      pose_at_scan_(start),
      odometry_at_scan_(start) {
  options_.slam = slam_.options();
}

ExplorationStep ExplorationRun::Step() {
  ExplorationStep out;
  if (done()) return out;
  // Advance to the next scan. Scans fall due at k / rate, so one period normally brings exactly
  // one; the loop only guards against rounding.
  const double period = 1.0 / options_.simulator.scan_rate_hz;
  bool got_scan = false;
  while (!got_scan) {
    StepResult result = simulator_.Step(period);
    out.collided = out.collided || result.collided;
    for (SimulatorEvent& event : result.events) {
      if (last_true_pose_) {
        summary_.distance_m += (event.true_pose.translation() - last_true_pose_->translation()).norm();
      }
      last_true_pose_ = event.true_pose;
      if (const auto* scan = std::get_if<LaserScan>(&event.data)) {
        AddScan(event, *scan, out);
        got_scan = true;
      }
      out.events.push_back(std::move(event));
    }
  }
  out.estimated_pose = pose_at_scan_;
  out.command = Steer(out);
  simulator_.SetCommand({out.command.linear, out.command.angular});
  if (!done() && time() >= options_.time_limit_s) state_ = ExplorationState::kTimeLimit;
  if (done()) simulator_.SetCommand({});
  return out;
}

void ExplorationRun::Run() {
  while (!done()) Step();
}

void ExplorationRun::AddScan(const SimulatorEvent& event, const LaserScan& scan, ExplorationStep& out) {
  out.slam = slam_.AddScan(scan);
  last_scan_ = scan;
  pose_at_scan_ = out.slam.filter.pose;
  odometry_at_scan_ = scan.odometry;
  const double error = (pose_at_scan_.translation() - event.true_pose.translation()).norm();
  ++summary_.scans;
  position_error_sum_ += error;
  summary_.max_position_error_m = std::max(summary_.max_position_error_m, error);
  summary_.final_position_error_m = error;
  map_to_world_ = event.true_pose * pose_at_scan_.inverse();
  true_poses_.push_back(event.true_pose);
  CollectNewHypotheses();
}

std::vector<MappedPose> ExplorationRun::MappedTrajectory() const {
  const std::vector<Pose2D> in_map = slam_.filter().Trajectory();
  std::vector<MappedPose> poses;
  for (std::size_t i = 0; i < std::min(in_map.size(), true_poses_.size()); ++i) {
    poses.push_back({true_poses_[i], in_map[i]});
  }
  return poses;
}

void ExplorationRun::CollectNewHypotheses() {
  // P-SLAM appends a hypothesis with its cells already validated against the best map, and
  // shrinks them only at later filter updates, so a copy taken now is the hypothesis as accepted.
  const std::vector<Hypothesis>& all = slam_.hypotheses();
  for (std::size_t i = accepted_.size(); i < all.size(); ++i) {
    accepted_.push_back(all[i]);
    accepted_map_to_world_.push_back(map_to_world_);
    hypothesis_arrived_ = true;
  }
}

Pose2D ExplorationRun::CurrentPoseEstimate() const {
  return pose_at_scan_ * Between(odometry_at_scan_, simulator_.odometry_pose());
}

bool ExplorationRun::Plan(const Pose2D& pose) {
  const bool skip = options_.explore.mode == ExploreMode::kSkipPredicted;
  for (int round = 0; round <= options_.max_skip_rounds; ++round) {
    ExploreRequest request;
    request.robot_position = pose.translation();
    request.blacklist = blacklist_;
    request.tried_way_ins = tried_way_ins_;
    if (target_ && !goal_reached_) request.current_goal = target_->position;
    if (skip) {
      request.covered = [this](const Eigen::Vector2i& cell) { return slam_.IsCovered(cell); };
      request.predicted_wall = [this](const Eigen::Vector2i& cell) { return slam_.IsPredictedWall(cell); };
      request.predicted = request.covered;
    }
    const auto started = std::chrono::steady_clock::now();
    const bool on_merged = skip && options_.plan_on_merged_map;
    // Office seed 2's skip run once stopped with 54 clusters unreachable on the merged map;
    // planned on its own map as well, the robot went on for 88 s.
    const OccupancyGrid& built = slam_.filter().best().map;
    const auto select = [&] {
      return on_merged ? SelectNextTargetOnMerged(slam_.MergedMap(), built, request, options_.explore)
                       : SelectNextTarget(built, request, options_.explore);
    };
    ExploreDecision decision = select();
    if (skip && options_.verify_pending_predictions && decision.done() && decision.skipped > 0) {
      request.covered = [settled = slam_.SettledCoverage()](const Eigen::Vector2i& cell) {
        return settled.Covered(cell);
      };
      decision = select();
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
    summary_.planning_ms += ms;
    summary_.max_planning_ms = std::max(summary_.max_planning_ms, ms);
    summary_.expanded_nodes += static_cast<double>(decision.expanded_nodes);
    ++summary_.plans;
    summary_.skipped_clusters = decision.skipped;
    hypothesis_arrived_ = false;
    goal_reached_ = false;
    if (decision.done()) {
      DropTarget();
      // Frontiers given up are still unexplored: forget the give-ups and try them again, as long
      // as the robot got somewhere since the last time. Otherwise it is stuck, not done.
      if (decision.blacklisted > 0 && !decision.start_blocked) {
        if (!reached_since_forgiving_) {
          state_ = ExplorationState::kStuck;
          return false;
        }
        blacklist_.clear();
        reached_since_forgiving_ = false;
        return Plan(pose);
      }
      if (decision.start_blocked && ++blocked_plans_ <= options_.max_blocked_plans) {
        look_around_until_ = time() + options_.look_around_s;
      } else {
        state_ = decision.start_blocked ? ExplorationState::kStuck : ExplorationState::kExplored;
      }
      return false;
    }
    blocked_plans_ = 0;
    const bool new_target = !target_ || target_->cell != decision.target->cell;
    target_ = decision.target;
    FollowerOptions follow = options_.follower;
    if (time() < careful_until_) {
      follow.lookahead_distance = std::min(follow.lookahead_distance, options_.careful_lookahead);
    }
    follower_ = PathFollower(follow);
    follower_.SetPath(target_->path);
    next_plan_time_ = time() + options_.replan_period_s;
    stopped_since_ = -1.0;
    if (!new_target) return true;
    ++summary_.targets;
    if (target_->way_in) ++summary_.way_ins;
    slam_.SetTarget(target_->cell, simulator_.time());
    if (options_.wait_for_predictions) {
      slam_.FlushPredictions();
      CollectNewHypotheses();
    }
    // A hypothesis for this very target may cover it: then choose again, skipping it.
    if (!skip || !hypothesis_arrived_) return true;
  }
  return true;
}

DriveCommand ExplorationRun::Steer(ExplorationStep& out) {
  const double now = time();
  const DriveCommand back_off{-options_.back_off_speed, 0.0};
  // A contact, or the obstacle stop holding the robot: both say where the robot stands, not that
  // the target is out of reach (a robot held by a door jamb it faces gave up every target behind
  // that door in turn). Back off and plan again with a shorter lookahead; only a second one within
  // careful_s gives the target up.
  const bool held = stopped_since_ >= 0.0 && now - stopped_since_ > options_.stuck_timeout_s;
  if (out.collided || held) {
    if (now < careful_until_) {
      GiveUpTarget();
    } else {
      DropTarget();
    }
    careful_until_ = now + options_.careful_s;
    stopped_since_ = -1.0;
    // Backing into something as well: stop backing and plan from here.
    const bool was_backing_off = backing_off_;
    backing_off_ = !was_backing_off;
    back_off_until_ = now + options_.back_off_s;
    if (backing_off_) return back_off;
  }
  if (backing_off_) {
    if (now < back_off_until_) return back_off;
    // Go on while the robot stands closer to a mapped wall than the planner's margin: planned
    // from there, the way out leaves along the wall it touched and touches it again.
    if (now < back_off_until_ + options_.max_extra_back_off_s &&
        InsideWallMargin(slam_.filter().best().map, CurrentPoseEstimate().translation())) {
      return back_off;
    }
    backing_off_ = false;
  }
  if (now < look_around_until_) return {0.0, 0.5};  // turn in place so the laser sees around
  const Pose2D pose = CurrentPoseEstimate();
  FollowerOutput follow = follower_.Update(pose);
  if (follow.goal_reached && target_) {
    reached_since_forgiving_ = true;
    goal_reached_ = true;
    if (target_->way_in) tried_way_ins_.push_back(target_->position);
  }
  const bool skip_mode = options_.explore.mode == ExploreMode::kSkipPredicted;
  const bool replan = !target_ || follow.goal_reached || now >= next_plan_time_ || (skip_mode && hypothesis_arrived_);
  if (replan) {
    out.planned = true;
    if (!Plan(pose)) return {};
    follow = follower_.Update(pose);
  }
  const DriveCommand command =
      last_scan_ ? ApplyObstacleStop(follow.command, *last_scan_, options_.obstacle_stop) : follow.command;
  if (command.linear < follow.command.linear) {
    if (stopped_since_ < 0.0) stopped_since_ = now;
  } else {
    stopped_since_ = -1.0;
  }
  return command;
}

bool ExplorationRun::InsideWallMargin(const OccupancyGrid& map, const Eigen::Vector2d& position) const {
  const PlannerOptions& planner = options_.explore.planner;
  const double margin = planner.robot_radius + planner.inflation_margin;
  const int reach = static_cast<int>(std::ceil(margin / map.resolution()));
  const Eigen::Vector2i centre = map.WorldToCell(position);
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const Eigen::Vector2i c = centre + Eigen::Vector2i(dx, dy);
      if ((map.CellCenter(c) - position).norm() > margin) continue;
      if (Classify(map, c, planner.classes) == CellClass::kOccupied) return true;
    }
  }
  return false;
}

void ExplorationRun::GiveUpTarget() {
  if (!target_) return;
  blacklist_.push_back(target_->position);
  ++summary_.given_up;
  DropTarget();
}

void ExplorationRun::DropTarget() {
  target_.reset();
  follower_.SetPath({});
}

ExplorationSummary ExplorationRun::Summary() const {
  ExplorationSummary s = summary_;
  s.state = state_;
  s.time_s = time();
  s.collisions = simulator_.collision_count();
  s.hypotheses = static_cast<int>(accepted_.size());
  s.slam = slam_.stats();
  s.mean_position_error_m = s.scans > 0 ? position_error_sum_ / s.scans : 0.0;
  return s;
}

}  // namespace pslam
