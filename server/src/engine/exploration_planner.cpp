#include "engine/exploration_planner.hpp"

#include <exception>
#include <utility>

#include "pslam/explore/frontier.hpp"

namespace pslam::server {

PlanResult Plan(const PlanRequest& request) {
  ExploreOptions options;
  options.mode = request.skip_predicted ? ExploreMode::kSkipPredicted : ExploreMode::kFullCoverage;
  ExploreRequest explore;
  explore.robot_position = request.pose.translation();
  explore.covered = [&coverage = request.coverage](const Eigen::Vector2i& cell) { return coverage.Covered(cell); };
  explore.predicted_wall = [&coverage = request.coverage](const Eigen::Vector2i& cell) {
    return coverage.PredictedWall(cell);
  };
  // Covered cells the map observed but has not decided count as predicted, not as undecided.
  explore.predicted = explore.covered;
  PlanResult result;
  result.pose = request.pose;
  result.time = request.time;
  result.target = SelectNextTarget(request.map, explore, options).target;
  for (const FrontierCluster& c : FindFrontierClusters(request.map, options.frontier)) {
    result.frontiers.push_back({c.centroid.x(), c.centroid.y()});
  }
  return result;
}

ExplorationPlanner::ExplorationPlanner(std::function<void()> ready)
    : ready_(std::move(ready)), worker_([this](std::stop_token stop) { Work(stop); }) {}

ExplorationPlanner::~ExplorationPlanner() {
  worker_.request_stop();
  wake_.notify_all();
}

bool ExplorationPlanner::Request(PlanRequest request) {
  {
    std::lock_guard lock(mutex_);
    if (busy_ || result_) return false;
    job_ = std::move(request);
    busy_ = true;
  }
  wake_.notify_one();
  return true;
}

std::optional<PlanResult> ExplorationPlanner::TakeResult() {
  std::lock_guard lock(mutex_);
  return std::exchange(result_, std::nullopt);
}

bool ExplorationPlanner::busy() {
  std::lock_guard lock(mutex_);
  return busy_ || result_.has_value();
}

void ExplorationPlanner::WaitIdle() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] { return !busy_; });
}

void ExplorationPlanner::Work(std::stop_token stop) {
  for (;;) {
    PlanRequest job;
    {
      std::unique_lock lock(mutex_);
      if (!wake_.wait(lock, stop, [&] { return job_.has_value(); })) return;
      job = std::move(*job_);
      job_.reset();
    }
    PlanResult result;
    try {
      result = Plan(job);
    } catch (const std::exception& e) {  // on this thread it would terminate the server
      result.error = e.what();
    }
    {
      std::lock_guard lock(mutex_);
      result_ = std::move(result);
    }
    if (ready_) ready_();
    {
      std::lock_guard lock(mutex_);
      busy_ = false;
    }
    idle_.notify_all();
  }
}

}  // namespace pslam::server
