#pragma once
// Exploration planning (frontiers, target selection, path) on a worker thread of its own, so that
// a plan never delays the filter or a scan's live tick. It plans on a snapshot of the best map and
// of the prediction coverage (copying a grid copies tile pointers only). One request at a time: a
// request made while one is running is dropped; the caller asks again at a later input. The result
// waits in a single slot; 'ready' is called on the worker when one is there, so the engine can take
// it without waiting for the next input.
#include <array>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <stop_token>
#include <thread>
#include <string>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/explore/explorer.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/slam/prediction_coverage.hpp"

namespace pslam::server {

struct PlanRequest {
  OccupancyGrid map;            // the best particle's map
  PredictionCoverage coverage;  // cells covered by active hypotheses (skip-predicted mode)
  Pose2D pose;                  // the robot's pose on that map
  bool skip_predicted = false;
  double time = 0.0;            // input time of the request
  // Skip-predicted: once only frontiers that predictions cover are left, go and verify them (plan
  // with full coverage) rather than stop.
  bool verify_predicted = true;
  std::vector<Eigen::Vector2d> blacklist{};  // targets given up (the robot made no progress towards them)
};

struct PlanResult {
  Pose2D pose;
  double time = 0.0;
  std::optional<ExploreTarget> target;  // empty: exploration is done (or blocked)
  std::vector<std::array<double, 2>> frontiers;  // cluster centroids
  std::string error;  // planning threw (out of memory, ...): the session's engine fails with this
  bool verifying = false;       // 'target' is a frontier predictions cover (skip mode, verify_predicted)
  bool start_blocked = false;   // the robot's position could not be left on the map
  int skipped = 0;              // frontier clusters left out as covered by predictions
  int unreachable = 0;          // frontier clusters no path reaches
  int blacklisted = 0;
  double mapped_m2 = 0.0;       // free area of the map
  double predicted_m2 = 0.0;    // area predictions cover that the map has not decided
};

class ExplorationPlanner {
 public:
  explicit ExplorationPlanner(std::function<void()> ready);
  ~ExplorationPlanner();  // stops after the current plan and joins
  ExplorationPlanner(const ExplorationPlanner&) = delete;
  ExplorationPlanner& operator=(const ExplorationPlanner&) = delete;

  // Starts planning; returns false, dropping the request, while a plan is running or waits to be taken.
  bool Request(PlanRequest request);
  std::optional<PlanResult> TakeResult();
  // True from an accepted Request() until its result is taken.
  bool busy();
  // Blocks until no plan is running and 'ready' was called for the last one (tests).
  void WaitIdle();

 private:
  void Work(std::stop_token stop);

  std::function<void()> ready_;
  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::condition_variable_any idle_;
  std::optional<PlanRequest> job_;
  bool busy_ = false;
  std::optional<PlanResult> result_;
  std::jthread worker_;  // last: starts after, and is joined before, everything it uses
};

// The plan itself, synchronous (the worker runs this).
PlanResult Plan(const PlanRequest& request);

}  // namespace pslam::server
