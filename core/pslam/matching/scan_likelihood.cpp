#include "pslam/matching/scan_likelihood.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {

ScanLikelihood ComputeScanLikelihood(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points,
                                     const Pose2D& pose, const LikelihoodOptions& o) {
  ScanLikelihood out;
  const double res = grid.resolution();
  const auto occupied = static_cast<OccupancyGrid::Cell>(
      std::lround(std::log(o.occupied_probability / (1.0 - o.occupied_probability)) / OccupancyGrid::kLogOddsPerUnit));
  const double max_d2 = std::pow((o.window_cells + 1) * res, 2);
  const double inv_2s2 = 1.0 / (2.0 * o.sigma * o.sigma);
  const std::size_t step = static_cast<std::size_t>(std::max(1, o.point_step));
  for (std::size_t k = 0; k < points.size(); k += step) {
    const Eigen::Vector2d w = pose * points[k].cast<double>();
    const Eigen::Vector2i c = grid.WorldToCell(w);
    double best = max_d2;
    bool near_known = grid.IsKnown(c.x(), c.y());
    for (int dy = -o.window_cells; dy <= o.window_cells; ++dy) {
      for (int dx = -o.window_cells; dx <= o.window_cells; ++dx) {
        const OccupancyGrid::Cell v = grid.At(c.x() + dx, c.y() + dy);
        if (v == OccupancyGrid::kUnknown || v < occupied) continue;
        near_known = true;
        best = std::min(best, (grid.CellCenter({c.x() + dx, c.y() + dy}) - w).squaredNorm());
      }
    }
    // An endpoint in unknown space scores like one far from any wall, so that a pose is never
    // rewarded for pushing its endpoints out of the map.
    ++(near_known ? out.explored_points : out.unexplored_points);
    out.log_likelihood -= best * inv_2s2;
  }
  return out;
}

}  // namespace pslam
