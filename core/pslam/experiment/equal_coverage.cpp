#include "pslam/experiment/equal_coverage.hpp"

#include <cmath>
#include <functional>
#include <limits>

#include "pslam/experiment/map_similarity.hpp"
#include "pslam/sim/flood_fill.hpp"

namespace pslam {

OccupancyGrid ReachableFreeCells(const World& world, const Eigen::Vector2d& start) {
  const std::vector<bool> reached =
      FloodFill4(world, world.WorldToCell(start), [&world](const Eigen::Vector2i& c) { return world.IsFree(c); });
  const CellBox& b = world.bounds();
  World reachable(world.resolution(), b, WorldCell::kUnknown);
  for (int y = b.min.y(); y < b.min.y() + b.height(); ++y) {
    for (int x = b.min.x(); x < b.min.x() + b.width(); ++x) {
      if (reached[BoundsIndex(world, {x, y})]) reachable.Set({x, y}, WorldCell::kFree);
    }
  }
  return reachable.ToGrid();
}

double MappedOrPredictedNow(const ExplorationRun& run, const OccupancyGrid& reachable) {
  std::vector<HypothesisCell> merged;
  if (run.options().slam.predict) {
    merged = MergedPredictedCells(run.slam(), [&run](int id) {
      for (std::size_t i = 0; i < run.accepted_hypotheses().size(); ++i) {
        if (run.accepted_hypotheses()[i].id == id) return run.accepted_map_to_world()[i];
      }
      return Pose2D();
    });
  }
  return MappedOrPredictedFraction(reachable, run.slam().filter().best().map, merged);
}

double CoverageTrace::TimeToReach(double fraction) const {
  for (const auto& [time, coverage] : samples) {
    if (coverage >= fraction) return time;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

CoverageTrace RunRecordingCoverage(ExplorationRun& run, const OccupancyGrid& reachable, double period_s,
                                   const std::function<void()>& on_step) {
  CoverageTrace trace;
  double next_sample = period_s;
  while (!run.done()) {
    run.Step();
    if (on_step) on_step();
    if (run.time() >= next_sample && !run.done()) {
      trace.samples.emplace_back(run.time(), MappedOrPredictedNow(run, reachable));
      next_sample += period_s;
    }
  }
  trace.samples.emplace_back(run.time(), MappedOrPredictedNow(run, reachable));
  return trace;
}

EqualCoverageSaving CompareAtEqualCoverage(const CoverageTrace& full, const CoverageTrace& skip, double tolerance) {
  EqualCoverageSaving s;
  s.target = full.Final() - tolerance;
  s.full_time_s = full.TimeToReach(s.target);
  s.skip_time_s = skip.TimeToReach(s.target);
  s.skip_reached = std::isfinite(s.skip_time_s);
  if (s.skip_reached && s.full_time_s > 0.0) s.saved_fraction = (s.full_time_s - s.skip_time_s) / s.full_time_s;
  return s;
}

}  // namespace pslam
