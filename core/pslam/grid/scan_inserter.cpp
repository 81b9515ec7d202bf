#include "pslam/grid/scan_inserter.hpp"

#include <cmath>

#include "pslam/grid/ray_caster.hpp"

namespace pslam {
namespace {
int MilliLogOdds(double p) { return static_cast<int>(std::lround(std::log(p / (1.0 - p)) / OccupancyGrid::kLogOddsPerUnit)); }
}  // namespace

ScanInserter::ScanInserter(const ScanInsertOptions& o)
    : hit_(MilliLogOdds(o.hit_probability)),
      miss_(MilliLogOdds(o.miss_probability)),
      lo_(MilliLogOdds(o.min_probability)),
      hi_(MilliLogOdds(o.max_probability)) {}

void ScanInserter::Insert(const ScanPoints& points, const Pose2D& pose, OccupancyGrid& grid,
                          OccupancyGrid* forget) const {
  const Eigen::Vector2i origin = grid.WorldToCell(pose * points.origin.cast<double>());
  auto miss = [&](int x, int y) {
    grid.AddLogOdds(x, y, miss_, lo_, hi_);
    if (forget) forget->Forget(x, y);
  };
  for (const auto& p : points.free_ends) {
    const Eigen::Vector2i end = grid.WorldToCell(pose * p.cast<double>());
    TraceRay(origin, end, miss);
    miss(end.x(), end.y());
  }
  for (const auto& p : points.hits) TraceRay(origin, grid.WorldToCell(pose * p.cast<double>()), miss);
  for (const auto& p : points.hits) {
    const Eigen::Vector2i end = grid.WorldToCell(pose * p.cast<double>());
    grid.AddLogOdds(end.x(), end.y(), hit_, lo_, hi_);
    if (forget) forget->Forget(end.x(), end.y());
  }
}

}  // namespace pslam
