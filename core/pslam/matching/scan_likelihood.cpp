#include "pslam/matching/scan_likelihood.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {
namespace {

struct NearestWall {
  bool near_known = false;  // the endpoint's cell or a wall in the window has been observed
  double distance2 = 0.0;   // squared distance to the nearest occupied cell, capped
};

NearestWall FindNearestWall(const OccupancyGrid& grid, const Eigen::Vector2d& w, const Eigen::Vector2i& c,
                            int window, OccupancyGrid::Cell occupied, double cap2) {
  NearestWall out{grid.IsKnown(c.x(), c.y()), cap2};
  for (int dy = -window; dy <= window; ++dy) {
    for (int dx = -window; dx <= window; ++dx) {
      const OccupancyGrid::Cell v = grid.At(c.x() + dx, c.y() + dy);
      if (v == OccupancyGrid::kUnknown || v < occupied) continue;
      out.near_known = true;
      out.distance2 = std::min(out.distance2, (grid.CellCenter({c.x() + dx, c.y() + dy}) - w).squaredNorm());
    }
  }
  return out;
}

}  // namespace

ScanLikelihood ComputeScanLikelihood(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points,
                                     const Pose2D& pose, const LikelihoodOptions& o, const OccupancyGrid* hypothesis) {
  ScanLikelihood out;
  const double res = grid.resolution();
  const auto occupied = static_cast<OccupancyGrid::Cell>(
      std::lround(std::log(o.occupied_probability / (1.0 - o.occupied_probability)) / OccupancyGrid::kLogOddsPerUnit));
  const double cap2 = std::pow((o.window_cells + 1) * res, 2);
  const double inv_2s2 = 1.0 / (2.0 * o.sigma * o.sigma);
  out.miss_log_likelihood = -cap2 * inv_2s2;
  const std::size_t step = static_cast<std::size_t>(std::max(1, o.point_step));
  for (std::size_t k = 0; k < points.size(); k += step) {
    const Eigen::Vector2d w = pose * points[k].cast<double>();
    const Eigen::Vector2i c = grid.WorldToCell(w);
    const NearestWall in_map = FindNearestWall(grid, w, c, o.window_cells, occupied, cap2);
    if (in_map.near_known) {
      ++out.explored_points;
      out.explored_log_likelihood -= in_map.distance2 * inv_2s2;
      continue;
    }
    ++out.unexplored_points;
    if (!hypothesis) continue;
    const NearestWall predicted = FindNearestWall(*hypothesis, w, c, o.window_cells, occupied, cap2);
    if (!predicted.near_known) continue;
    ++out.hypothesis_points;
    out.hypothesis_log_likelihood -= predicted.distance2 * inv_2s2;
    if (predicted.distance2 < cap2) ++out.hypothesis_hits;
  }
  return out;
}

}  // namespace pslam
