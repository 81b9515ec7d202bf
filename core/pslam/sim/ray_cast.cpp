#include "pslam/sim/ray_cast.hpp"

#include <cmath>
#include <limits>

namespace pslam {

double CastRay(const World& world, const Eigen::Vector2d& origin, double angle, double max_range) {
  const double res = world.resolution();
  const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
  Eigen::Vector2i cell = world.WorldToCell(origin);
  if (world.IsOccupied(cell)) return 0.0;
  const bool started_inside = world.Contains(cell);

  constexpr double kInf = std::numeric_limits<double>::infinity();
  const int step_x = dir.x() > 0.0 ? 1 : -1;
  const int step_y = dir.y() > 0.0 ? 1 : -1;
  // Ray parameter (= distance, dir is a unit vector) at which the next x / y cell boundary is crossed.
  double next_x = kInf, next_y = kInf, delta_x = kInf, delta_y = kInf;
  if (dir.x() != 0.0) {
    next_x = ((cell.x() + (step_x > 0 ? 1 : 0)) * res - origin.x()) / dir.x();
    delta_x = res / std::abs(dir.x());
  }
  if (dir.y() != 0.0) {
    next_y = ((cell.y() + (step_y > 0 ? 1 : 0)) * res - origin.y()) / dir.y();
    delta_y = res / std::abs(dir.y());
  }

  while (true) {
    double t;
    if (next_x < next_y) {
      t = next_x;
      next_x += delta_x;
      cell.x() += step_x;
    } else {
      t = next_y;
      next_y += delta_y;
      cell.y() += step_y;
    }
    if (t >= max_range) return max_range;
    if (world.IsOccupied(cell)) return t;
    // The bounds are a box: a ray that started inside and left it can never come back.
    if (started_inside && !world.Contains(cell)) return max_range;
  }
}

}  // namespace pslam
