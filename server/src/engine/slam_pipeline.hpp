#pragma once
// The seam between the server and the SLAM core: one session's P-SLAM, called from one thread
// (SessionEngine runs it on the session's thread; the structure predictor and the exploration
// planner run on workers of their own). Besides the filter it yields what the live view, the
// storage and the agent need: hypotheses as they change, frontiers, and the next exploration target
// with its path (for sessions with a robot to drive; replays infer targets from the heading).
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <utility>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/exploration_planner.hpp"
#include "engine/fixed_map_localization.hpp"
#include "engine/site_library.hpp"
#include "model/hypothesis.hpp"
#include "model/input.hpp"
#include "model/session_settings.hpp"
#include "pslam/filter/divergence_monitor.hpp"
#include "pslam/slam/pslam.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam::server {

// Where exploration stands, as the operator sees it (sessions that plan targets).
struct ExplorationStatus {
  // "exploring", "verifying" (visiting frontiers predictions cover), "waiting_for_verification"
  // (only such frontiers are left and verifying is off), "complete" or "blocked" (no target can be
  // reached from where the robot is); empty before the first plan.
  std::string state;
  std::string reason;           // why, in words, for the states that end or pause exploration
  double mapped_m2 = 0.0;       // free area mapped
  double predicted_m2 = 0.0;    // area predictions cover that is not mapped yet
  int predicted_frontiers = 0;  // frontier clusters predictions cover
  double t = 0.0;               // input time of the plan
};

// The robot made no progress towards its target for a while; the target was given up.
struct StuckReport {
  double t = 0.0;
  double x = 0.0, y = 0.0;      // robot position
  double target_x = 0.0, target_y = 0.0;
  double seconds = 0.0;         // input time without progress
};

// What one input changed.
struct PipelineStep {
  std::shared_ptr<const LaserScan> scan;          // the scan the filter took; null for odometry
  RbpfStep filter;                                // for scans
  std::vector<HypothesisRecord> hypotheses_changed;  // added or updated by this input
  std::vector<std::int64_t> hypotheses_removed;
  std::optional<ExplorationTarget> target;        // a newly planned target, if any (see TakePlan)
  bool tracking_changed = false;                  // the divergence monitor's state changed
  std::optional<StuckReport> stuck;               // the target was given up at this input
};

// The LaserScan for a stored scan input of a session with laser 'laser'. Ranges that are not
// finite (NaN: no return) stay so; the filter treats them as beams without a return. Throws
// std::runtime_error when the number of ranges is not the laser's beam count.
LaserScan ToLaserScan(const InputRecord& input, const LaserGeometry& laser);

// The session's memory limit in bytes, and how many tile slots its grids may hold under it.
double MemoryLimitBytes(const SessionSettings& settings);
std::size_t MaxTileSlots(const SessionSettings& settings);

// P-SLAM options for a session; throws std::invalid_argument on a bad predictor setting.
PSlamOptions ToPSlamOptions(const SessionSettings& settings);

class SlamPipeline {
 public:
  // 'plan_ready' is called on the planner's thread when a plan can be taken (TakePlan). In localize
  // mode (settings.mode) 'fixed_map' is the site's map: the pipeline localizes on it and maps
  // nothing; throws std::invalid_argument without one or for bad localization settings. In extend
  // mode it localizes on it the same way until the localizer says localized, then maps on from
  // there: every particle's map starts as the site's map (RbpfOptions::prior_map), the first scan
  // at the localized pose. In map mode 'library' (site_library.hpp) is searched by the predictor
  // too; its features are extracted here.
  SlamPipeline(const SessionSettings& settings, const LaserGeometry& laser, std::function<void()> plan_ready = {},
               std::shared_ptr<const OccupancyGrid> fixed_map = nullptr, std::vector<SiteLibraryMap> library = {});
  SlamPipeline(const SlamPipeline&) = delete;
  SlamPipeline& operator=(const SlamPipeline&) = delete;

  // Throws std::runtime_error("memory limit: ...") once the session's grids exceed its memory
  // limit or refused a cell for it: the session must fail then.
  PipelineStep Add(const InputRecord& input);
  // Applies a finished plan: frontiers, and the new target (returned) if it is one the robot must
  // be sent. Add() does this too; call it when the planner says a plan is ready and no input is.
  std::optional<ExplorationTarget> TakePlan();

  // The best particle's map; in localize mode the fixed map (shown from the start).
  const OccupancyGrid& map() const { return localization_ ? localization_->map() : slam_->filter().best().map; }
  bool started() const { return localization_ || !slam_->filter().particles().empty(); }
  const RbpfStats& filter_stats() const { return localization_ ? localization_->stats() : slam_->filter().stats(); }
  PSlamStats pslam_stats() const { return slam_ ? slam_->stats() : PSlamStats{}; }
  int particle_count() const;
  std::vector<Pose2D> ParticlePoses() const;
  std::vector<double> Weights() const { return localization_ ? localization_->weights() : slam_->filter().Weights(); }
  // The best particle's pose at every scan so far (smoothed: see Rbpf::Trajectory); in localize
  // mode the estimate at every scan.
  std::vector<Pose2D> Trajectory() const;
  // Localize mode, and extend mode until localized (localizing()): re-localize from a pose, and how
  // sure the filter is.
  bool localizing() const { return localization_ != nullptr; }
  // What the pipeline does now: "map", "localize", or in extend mode "extend_localize" and then
  // "extend_map".
  std::string phase() const;
  void SetPose(const InitialPose& pose) { localization_->SetPose(pose); }
  LocalizationStats localization() const { return localization_->status(); }
  // Whether the filter looks lost, from every scan so far.
  const DivergenceMonitor& divergence() const { return divergence_; }

  const std::vector<HypothesisRecord>& hypotheses() const { return hypotheses_; }
  const std::vector<std::array<double, 2>>& frontiers() const { return frontiers_; }
  const std::optional<ExplorationTarget>& target() const { return target_; }
  const ExplorationStatus& exploration() const { return exploration_; }
  // True once after each plan that changed the exploration state (not merely its reason).
  bool TakeExplorationChange() { return std::exchange(exploration_changed_, false); }
  // Skip-predicted mode: whether frontiers covered by predictions are visited once no other is left
  // (true), or the robot waits there for the operator. Takes effect at the next plan.
  void SetVerifyPredicted(bool verify) { verify_predicted_ = verify; }

 private:
  HypothesisRecord ToRecord(const Hypothesis& h) const;
  Pose2D CurrentPose() const;
  void CheckMemory() const;
  void MaybeRequestPlan(double time);
  void WatchProgress(double time, PipelineStep& step);
  void UpdateExploration(const PlanResult& plan);
  // Localize mode: once per search for the robot's place, the robot turns all the way round.
  void LookAroundWhileSearching(PipelineStep& step);
  // Extend mode, once localized at 'pose': mapping takes over from the localizer.
  void StartMapping(const Pose2D& pose);

  SessionSettings settings_;
  LaserGeometry laser_;
  std::vector<SiteLibraryMap> library_;           // what hypotheses' reference_map ids name
  std::unique_ptr<PSlam> slam_;                   // built when mapping starts
  std::unique_ptr<FixedMapLocalization> localization_;  // localize mode; extend mode until localized
  std::vector<Pose2D> localized_trajectory_;      // extend mode: the estimates before mapping took over
  DivergenceMonitor divergence_;
  std::vector<HypothesisRecord> hypotheses_;
  std::map<int, std::size_t> record_index_;       // hypothesis id -> index in hypotheses_
  std::vector<std::array<double, 2>> frontiers_;
  std::optional<ExplorationTarget> target_;
  double last_plan_time_ = -1e300;
  bool exploration_done_ = false;
  bool looked_around_ = false;                    // during this search for the robot's place
  ExplorationStatus exploration_;
  bool exploration_changed_ = false;
  bool verify_predicted_ = true;
  std::vector<Eigen::Vector2d> blacklist_;        // targets given up
  std::optional<Pose2D> progress_anchor_;         // where the robot was when it last made progress
  double progress_anchor_time_ = 0.0;
  std::unique_ptr<ExplorationPlanner> planner_;  // last: its worker reads nothing of ours
};

}  // namespace pslam::server
