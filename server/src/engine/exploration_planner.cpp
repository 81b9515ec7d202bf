#include "engine/exploration_planner.hpp"

#include <exception>
#include <utility>

#include "pslam/explore/cell_class.hpp"
#include "pslam/explore/frontier.hpp"

namespace pslam::server {
namespace {

// Mapped free area, and the area predictions cover that the map has not decided (walls and free
// space alike): what the operator sees as explored and as predicted.
void MeasureAreas(const PlanRequest& request, PlanResult& result) {
  const double cell_m2 = request.map.resolution() * request.map.resolution();
  const CellClassOptions classes;
  std::size_t free = 0;
  const OccupancyGrid& map = request.map;
  for (int ty = 0; ty < map.tiles_high(); ++ty) {
    for (int tx = 0; tx < map.tiles_wide(); ++tx) {
      const OccupancyGrid::Tile* tile = map.TileAt(map.tile_origin().x() + tx, map.tile_origin().y() + ty);
      if (tile == nullptr) continue;
      for (const OccupancyGrid::Cell v : tile->cells) {
        if (v != OccupancyGrid::kUnknown && CellProbability(v) < classes.free_below) ++free;
      }
    }
  }
  std::size_t predicted = 0;
  const OccupancyGrid& covering = request.coverage.covering();
  for (int ty = 0; ty < covering.tiles_high(); ++ty) {
    for (int tx = 0; tx < covering.tiles_wide(); ++tx) {
      const Eigen::Vector2i tile_xy = covering.tile_origin() + Eigen::Vector2i(tx, ty);
      const OccupancyGrid::Tile* tile = covering.TileAt(tile_xy.x(), tile_xy.y());
      if (tile == nullptr) continue;
      for (int i = 0; i < OccupancyGrid::kTileSize * OccupancyGrid::kTileSize; ++i) {
        if (tile->cells[static_cast<std::size_t>(i)] == OccupancyGrid::kUnknown) continue;
        const Eigen::Vector2i cell = tile_xy * OccupancyGrid::kTileSize +
                                     Eigen::Vector2i(i & OccupancyGrid::kTileMask, i >> OccupancyGrid::kTileBits);
        if (Classify(map, cell, classes) == CellClass::kUnknown) ++predicted;
      }
    }
  }
  result.mapped_m2 = static_cast<double>(free) * cell_m2;
  result.predicted_m2 = static_cast<double>(predicted) * cell_m2;
}

}  // namespace

PlanResult Plan(const PlanRequest& request) {
  ExploreOptions options;
  options.mode = request.skip_predicted ? ExploreMode::kSkipPredicted : ExploreMode::kFullCoverage;
  ExploreRequest explore;
  explore.robot_position = request.pose.translation();
  explore.blacklist = request.blacklist;
  explore.covered = [&coverage = request.coverage](const Eigen::Vector2i& cell) { return coverage.Covered(cell); };
  explore.predicted_wall = [&coverage = request.coverage](const Eigen::Vector2i& cell) {
    return coverage.PredictedWall(cell);
  };
  // Covered cells the map observed but has not decided count as predicted, not as undecided.
  explore.predicted = explore.covered;
  PlanResult result;
  result.pose = request.pose;
  result.time = request.time;
  ExploreDecision decision = SelectNextTarget(request.map, explore, options);
  result.skipped = decision.skipped;
  if (!decision.target && decision.skipped > 0 && request.verify_predicted) {
    // Only predicted frontiers are left: visit them too, so the whole area ends up observed.
    options.mode = ExploreMode::kFullCoverage;
    decision = SelectNextTarget(request.map, explore, options);
    result.verifying = decision.target.has_value();
  }
  result.target = std::move(decision.target);
  result.start_blocked = decision.start_blocked;
  result.unreachable = decision.unreachable;
  result.blacklisted = decision.blacklisted;
  MeasureAreas(request, result);
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
