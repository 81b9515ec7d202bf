#include "pslam/matching/scan_likelihood.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {
namespace {

struct NearestWall {
  bool near_known = false;  // the endpoint's cell or a wall in the window has been observed
  double distance2 = 0.0;   // squared distance to the nearest occupied cell, capped
};

// toward_sensor: one cell step toward the sensor, or zero to skip the free-space check.
NearestWall FindNearestWall(const OccupancyGrid& grid, const Eigen::Vector2d& w, const Eigen::Vector2i& c,
                            const Eigen::Vector2i& toward_sensor, int window, OccupancyGrid::Cell occupied,
                            double cap2) {
  NearestWall out{grid.IsKnown(c.x(), c.y()), cap2};
  for (int dy = -window; dy <= window; ++dy) {
    for (int dx = -window; dx <= window; ++dx) {
      const Eigen::Vector2i q(c.x() + dx, c.y() + dy);
      const OccupancyGrid::Cell v = grid.At(q.x(), q.y());
      if (v == OccupancyGrid::kUnknown || v < occupied) continue;
      out.near_known = true;
      if (toward_sensor != Eigen::Vector2i::Zero()) {
        const Eigen::Vector2i front = q + toward_sensor;
        const OccupancyGrid::Cell f = grid.At(front.x(), front.y());
        if (f != OccupancyGrid::kUnknown && f >= occupied) continue;
      }
      out.distance2 = std::min(out.distance2, (grid.CellCenter(q) - w).squaredNorm());
    }
  }
  return out;
}

// The 8-neighbour step that points most nearly from the endpoint back to the sensor.
Eigen::Vector2i StepTowardSensor(const Eigen::Vector2d& endpoint, const Eigen::Vector2d& sensor) {
  const Eigen::Vector2d d = sensor - endpoint;
  const double n = std::max(std::abs(d.x()), std::abs(d.y()));
  if (n <= 0.0) return Eigen::Vector2i::Zero();
  return {static_cast<int>(std::lround(d.x() / n)), static_cast<int>(std::lround(d.y() / n))};
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
    const Eigen::Vector2i toward_sensor =
        o.free_space_check ? StepTowardSensor(w, pose.translation()) : Eigen::Vector2i::Zero();
    const NearestWall in_map = FindNearestWall(grid, w, c, toward_sensor, o.window_cells, occupied, cap2);
    if (in_map.near_known) {
      ++out.explored_points;
      out.explored_log_likelihood -= in_map.distance2 * inv_2s2;
      continue;
    }
    ++out.unexplored_points;
    if (!hypothesis) continue;
    const NearestWall predicted = FindNearestWall(*hypothesis, w, c, toward_sensor, o.window_cells, occupied, cap2);
    if (!predicted.near_known) continue;
    ++out.hypothesis_points;
    out.hypothesis_log_likelihood -= predicted.distance2 * inv_2s2;
    if (predicted.distance2 < cap2) ++out.hypothesis_hits;
  }
  return out;
}

}  // namespace pslam
