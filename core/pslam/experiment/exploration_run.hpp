#pragma once
// One simulated exploration with P-SLAM in the loop, as in the paper's simulations (Sec. V-A):
// a simulated Pioneer 3-DX with its laser, the particle filter (with or without the structure
// predictor), frontier exploration in full-coverage or skip-predicted mode, a path follower and an
// obstacle stop, all on the simulator's clock.
//
// The robot knows only what SLAM knows: it plans on the best particle's map from the best pose,
// and follows the path from that pose, carried forward by odometry between scans. The simulator's
// ground truth is used for nothing but the report (distance driven, pose error). Every planned
// target is the P-SLAM target T_k, so the predictor predicts exactly where the robot means to go
// (once per goal: a replanned target near the last predicted one starts no new prediction);
// in skip-predicted mode a target that a new hypothesis covers is dropped at once and the explorer
// chooses again, which is how P-SLAM saves exploration time.
//
// Deterministic for a seed (simulator and filter): with wait_for_predictions the loop waits on the
// wall clock for each prediction to finish, so a prediction is never early or late in simulated
// time because the machine was busy.
#include <cstddef>
#include <optional>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/experiment/mapping_trajectory.hpp"
#include "pslam/explore/explorer.hpp"
#include "pslam/explore/obstacle_stop.hpp"
#include "pslam/explore/path_follower.hpp"
#include "pslam/predict/hypothesis.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world.hpp"
#include "pslam/slam/pslam.hpp"

namespace pslam {

struct ExplorationOptions {
  // slam.predict = false runs the plain RBPF. slam.filter.initial_pose is overwritten with the
  // start pose, so that the SLAM map frame is the world frame and results compare with the truth,
  // and slam.predict_on_merged_map with plan_on_merged_map in skip-predicted mode.
  PSlamOptions slam;
  ExploreOptions explore;             // explore.mode: full coverage or skip-predicted
  FollowerOptions follower;
  ObstacleStopOptions obstacle_stop;
  SimulatorOptions simulator;
  double time_limit_s = 3600.0;       // simulated seconds; the run stops there, unfinished
  double replan_period_s = 8.0;       // fold newly mapped space into the route this often
  double stuck_timeout_s = 3.0;       // held by the obstacle stop this long: treated as a contact
  // After a collision: reverse back_off_s at back_off_speed, plan again, and for careful_s follow
  // paths with careful_lookahead. Pure pursuit cuts a corner by part of its lookahead, and at a
  // 1 m door that cut is what touches the jamb. Only a collision within careful_s of another gives
  // the target up; when every contact did, a robot pressed against a jamb gave up each target
  // behind that door in turn, and the run ended as explored with most of the floor unseen.
  double back_off_s = 1.5;
  double back_off_speed = 0.1;        // m/s
  double careful_s = 30.0;
  double careful_lookahead = 0.25;    // m
  // After back_off_s, backing off goes on for up to this long while the robot is still within
  // the planner's wall margin (robot radius + inflation margin) of a mapped wall.
  double max_extra_back_off_s = 5.0;
  // Per planning, how often a target may be re-chosen because its own prediction covered it.
  int max_skip_rounds = 4;
  // Skip-predicted only: plan on P-SLAM's merged map (the paper's "virtual mapping", Sec. II-B)
  // instead of the best map, so predicted cells count as mapped and a region whose predictions
  // close it off leaves no frontier to visit. Paths may then cross predicted free space; the
  // obstacle stop and the give-up timeout handle predictions that turn out wrong. On the best map,
  // a frontier is skipped once the first skip_radius of unknown space behind it is predicted, and
  // whatever lies farther is never visited nor predicted: in the maze (seeds 1-3) such runs ended
  // with 13 % of the free area neither mapped nor predicted, against 0.2 % on the merged map.
  // The predictor then predicts from the merged map too (PSlamOptions::predict_on_merged_map).
  bool plan_on_merged_map = true;
  // Skip-predicted only: once every frontier left is skipped, frontiers covered only by pending
  // hypotheses (neither confirmed nor expired, PSlam::SettledCoverage) are visited too, so the
  // run does not end on predictions nothing has checked. A chain of wrong predictions can cover
  // every frontier: a generated office's skip run once ended at 241 s with 39 % of the floor
  // mapped or predicted, on 9 hypotheses of which 8 were pending (full coverage: 98.9 %).
  bool verify_pending_predictions = true;
  // Wait (on the wall clock) for the prediction of each new target, so that a run is the same
  // whatever the machine's load; false: predictions arrive when the worker is done, as on a robot.
  bool wait_for_predictions = true;
  // Plans that cannot leave the robot's cell (it sits in unknown or inflated space) turn the
  // robot in place to look around; after this many in a row the run ends as stuck.
  int max_blocked_plans = 10;
  double look_around_s = 2.0;         // simulated seconds of turning per blocked plan
};

// The defaults, with the filter's scan points set for the simulated LMS-200: its beams without a
// return read exactly max_range, and carving free space along them is what lets the explorer
// close long corridors.
ExplorationOptions DefaultExplorationOptions();

// A time limit that lets full coverage of 'world' finish: kExplorationSecondsPerFreeM2 simulated
// seconds per m² of its free area, at least kMinExplorationTimeS. The most furnished floors took up
// to 5.7 s per m² at the paper's 0.2 m/s (docs/experiments.md); a fixed limit ends large worlds
// unfinished for want of time.
inline constexpr double kExplorationSecondsPerFreeM2 = 8.0;
inline constexpr double kMinExplorationTimeS = 2400.0;
double ExplorationTimeBudget(const World& world);

enum class ExplorationState {
  kRunning,
  kExplored,    // no frontier left that is reachable, not blacklisted and (skip mode) not covered
  kTimeLimit,
  kStuck,       // the robot could not leave its cell max_blocked_plans times in a row, or only
                // frontiers it gave up are left and it reached no goal since it last retried them
};
const char* ExplorationStateName(ExplorationState state);

// What one Step() did.
struct ExplorationStep {
  std::vector<SimulatorEvent> events;  // odometry readings and scans emitted, with the truth
  PSlamStep slam;                      // of the last scan among them
  Pose2D estimated_pose;               // best SLAM pose at that scan
  DriveCommand command;                // sent to the robot until the next step
  bool planned = false;                // a new target was chosen
  bool collided = false;               // the simulator stopped a motion at an obstacle
};

struct ExplorationSummary {
  ExplorationState state = ExplorationState::kRunning;
  double time_s = 0.0;                 // simulated, from the start
  double distance_m = 0.0;             // driven, along the true path
  std::size_t collisions = 0;
  int scans = 0;
  int plans = 0;                       // calls to the explorer
  double planning_ms = 0.0;            // wall time spent choosing targets, all plans
  double max_planning_ms = 0.0;        // the slowest plan
  double expanded_nodes = 0.0;         // cells the path searches settled, all plans
  int way_ins = 0;                     // targets that were the way into space predictions sealed off
  int targets = 0;                     // distinct targets chosen (each is a P-SLAM target T_k)
  int given_up = 0;                    // targets blacklisted after a repeated collision or a long stop
  int skipped_clusters = 0;            // frontier clusters skipped as covered at the last plan
  int hypotheses = 0;                  // accepted
  PSlamStats slam;
  // |estimated - true| position of every scan, metres.
  double mean_position_error_m = 0.0;
  double max_position_error_m = 0.0;
  double final_position_error_m = 0.0;
};

class ExplorationRun {
 public:
  // Throws std::invalid_argument when the start is not free (see Simulator), or when the predictor
  // options are invalid.
  ExplorationRun(World world, const Pose2D& start, const ExplorationOptions& options);
  // It owns the filter's threads and the predictor's worker.
  ExplorationRun(const ExplorationRun&) = delete;
  ExplorationRun& operator=(const ExplorationRun&) = delete;

  // Advances the simulation to the next laser scan, gives it to P-SLAM, and steers: plans when
  // needed, follows the path, stops short of obstacles. Does nothing once done().
  ExplorationStep Step();
  // Steps until done().
  void Run();

  bool done() const { return state_ != ExplorationState::kRunning; }
  ExplorationState state() const { return state_; }
  double time() const { return simulator_.time() - options_.simulator.start_time_seconds; }
  ExplorationSummary Summary() const;

  const PSlam& slam() const { return slam_; }
  const Simulator& simulator() const { return simulator_; }
  const ExplorationOptions& options() const { return options_; }
  // The target being driven to, in the SLAM map frame.
  const std::optional<ExploreTarget>& target() const { return target_; }
  // Every accepted hypothesis as it was when accepted (P-SLAM's own copies shrink as the robot
  // observes their cells), in acceptance order.
  const std::vector<Hypothesis>& accepted_hypotheses() const { return accepted_; }
  // For each accepted hypothesis, the transform from the SLAM map frame to the world at the time
  // it was accepted: true pose * estimated pose^-1 (ground truth, for evaluation only). The map
  // frame starts as the world frame but slips where scan matching does (long corridors); the map
  // around the robot is consistent with its estimate, so this carries a prediction into the world
  // frame to be compared with the truth.
  const std::vector<Pose2D>& accepted_map_to_world() const { return accepted_map_to_world_; }
  // At every scan so far, the true pose and the best particle's (corrected) pose in the map frame:
  // where the built map has each place (mapping_trajectory.hpp).
  std::vector<MappedPose> MappedTrajectory() const;

 private:
  void AddScan(const SimulatorEvent& event, const LaserScan& scan, ExplorationStep& out);
  void CollectNewHypotheses();
  Pose2D CurrentPoseEstimate() const;
  // Chooses the next target; returns false when there is none (state_ or look-around set).
  bool Plan(const Pose2D& pose);
  DriveCommand Steer(ExplorationStep& out);
  // Whether an occupied cell of 'map' lies within the planner's wall margin of 'position'.
  bool InsideWallMargin(const OccupancyGrid& map, const Eigen::Vector2d& position) const;
  // Blacklists the current target, if any, and drops it.
  void GiveUpTarget();
  // Forgets the current target and its path, so that the next step plans.
  void DropTarget();

  ExplorationOptions options_;
  Simulator simulator_;
  PSlam slam_;
  PathFollower follower_;
  ExplorationState state_ = ExplorationState::kRunning;

  std::optional<LaserScan> last_scan_;
  Pose2D pose_at_scan_;            // SLAM estimate at the last scan
  Pose2D odometry_at_scan_;        // the raw odometry at that scan
  std::optional<Pose2D> last_true_pose_;

  std::optional<ExploreTarget> target_;
  std::vector<Eigen::Vector2d> blacklist_;
  std::vector<Eigen::Vector2d> tried_way_ins_;  // way-in exits reached (ExploreOptions::way_in_cost_factor)
  double next_plan_time_ = 0.0;
  double stopped_since_ = -1.0;    // simulated time the obstacle stop began holding the robot
  double look_around_until_ = -1.0;
  double back_off_until_ = -1.0;
  bool backing_off_ = false;
  double careful_until_ = -1.0;
  int blocked_plans_ = 0;
  bool reached_since_forgiving_ = true;  // a goal was reached since the blacklist was last cleared
  bool hypothesis_arrived_ = false;  // since the last plan
  bool goal_reached_ = false;        // the current target was reached since the last plan

  std::vector<Hypothesis> accepted_;
  std::vector<Pose2D> accepted_map_to_world_;
  Pose2D map_to_world_;            // as of the last scan
  ExplorationSummary summary_;
  double position_error_sum_ = 0.0;
  std::vector<Pose2D> true_poses_;  // at every scan given to P-SLAM
};

}  // namespace pslam
