#include "pslam/grid/stale_prior.hpp"

#include "pslam/grid/ray_caster.hpp"

namespace pslam {
namespace {

bool Free(OccupancyGrid::Cell c) { return c != OccupancyGrid::kUnknown && c < 0; }

// A hit this close to one of the prior's walls is that wall, seen from a pose a cell or two off
// (or along it at a grazing angle), not something new.
constexpr int kWallTolerance = 2;  // cells

bool NearPriorWall(const OccupancyGrid& prior, const Eigen::Vector2i& cell) {
  for (int dy = -kWallTolerance; dy <= kWallTolerance; ++dy) {
    for (int dx = -kWallTolerance; dx <= kWallTolerance; ++dx) {
      const OccupancyGrid::Cell c = prior.At(cell.x() + dx, cell.y() + dy);
      if (c != OccupancyGrid::kUnknown && c > 0) return true;
    }
  }
  return false;
}

}  // namespace

int ForgetPriorFloorBehindNewSurfaces(const ScanPoints& points, const Pose2D& pose, const OccupancyGrid& prior,
                                      double depth, OccupancyGrid& map) {
  if (!(depth > 0.0)) return 0;
  int forgotten = 0;
  const Eigen::Vector2d origin = pose * points.origin.cast<double>();
  for (const auto& p : points.hits) {
    const Eigen::Vector2d hit = pose * p.cast<double>();
    const Eigen::Vector2i end = map.WorldToCell(hit);
    if (!Free(prior.At(end.x(), end.y())) || NearPriorWall(prior, end)) continue;
    const Eigen::Vector2d beam = hit - origin;
    const double range = beam.norm();
    if (range <= 0.0) continue;
    const Eigen::Vector2i far = map.WorldToCell(hit + beam * (depth / range));
    bool stopped = false;
    // TraceRay includes its start: the hit cell is this scan's, neither forgotten nor a stop.
    TraceRay(end, far, [&](int x, int y) {
      if (stopped || (x == end.x() && y == end.y())) return;
      const OccupancyGrid::Cell now = map.At(x, y), before = prior.At(x, y);
      if (!Free(before)) {
        stopped = true;  // the prior's wall or unknown space: what stood there before
      } else if (now == before) {
        map.Forget(x, y);
        ++forgotten;
      } else if (Free(now)) {
        stopped = true;  // floor this session has seen: the new surface ends before it
      }
    });
  }
  return forgotten;
}

}  // namespace pslam
