#pragma once
// Integer ray traversal (Bresenham) between two cells.
#include <Eigen/Core>
#include <cstdlib>

namespace pslam {

// Calls visit(x, y) for every cell from `from` up to, but not including, `to`.
template <typename Visit>
void TraceRay(const Eigen::Vector2i& from, const Eigen::Vector2i& to, Visit&& visit) {
  int x = from.x(), y = from.y();
  const int dx = std::abs(to.x() - x), dy = -std::abs(to.y() - y);
  const int sx = x < to.x() ? 1 : -1, sy = y < to.y() ? 1 : -1;
  int err = dx + dy;
  while (x != to.x() || y != to.y()) {
    visit(x, y);
    const int e2 = 2 * err;
    if (e2 >= dy) { err += dy; x += sx; }
    if (e2 <= dx) { err += dx; y += sy; }
  }
}

}  // namespace pslam
