#include "pslam/sim/world_painter.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {
namespace {

// First cell index whose centre is at or above 'v': centre (i + 0.5) * res >= v.
int FirstCellAtOrAbove(double v, double res) { return static_cast<int>(std::ceil(v / res - 0.5 - 1e-9)); }

// Calls visit(cell, centre) for every cell whose centre lies in the box [lo, hi] (clipped to the world).
template <typename Visit>
void ForCentresIn(const World& world, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, Visit&& visit) {
  const double res = world.resolution();
  const CellBox& b = world.bounds();
  const int x0 = std::max(FirstCellAtOrAbove(lo.x(), res), b.min.x());
  const int y0 = std::max(FirstCellAtOrAbove(lo.y(), res), b.min.y());
  const int x1 = std::min(FirstCellAtOrAbove(hi.x(), res), b.max.x());
  const int y1 = std::min(FirstCellAtOrAbove(hi.y(), res), b.max.y());
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) visit(Eigen::Vector2i(x, y), world.CellCenter({x, y}));
  }
}

}  // namespace

World MakeWalledRoom(double length, double width, double wall_thickness, double resolution) {
  const int wall = static_cast<int>(std::lround(wall_thickness / resolution));
  CellBox bounds;
  bounds.min = {-wall, -wall};
  bounds.max = {static_cast<int>(std::lround(length / resolution)) + wall - 1,
                static_cast<int>(std::lround(width / resolution)) + wall - 1};
  World world(resolution, bounds, WorldCell::kOccupied);
  FillBox(world, {0.0, 0.0}, {length, width}, WorldCell::kFree);
  return world;
}

void FillBox(World& world, const Eigen::Vector2d& min, const Eigen::Vector2d& max, WorldCell value) {
  // Rounded, not floored, so that 2.2 / 0.05 = 43.99999... still starts at cell 44.
  const double res = world.resolution();
  const int x0 = static_cast<int>(std::lround(min.x() / res)), x1 = static_cast<int>(std::lround(max.x() / res));
  const int y0 = static_cast<int>(std::lround(min.y() / res)), y1 = static_cast<int>(std::lround(max.y() / res));
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) world.Set({x, y}, value);
  }
}

void FillSegment(World& world, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double thickness, WorldCell value) {
  const double half = thickness / 2.0;
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const Eigen::Vector2d pad = Eigen::Vector2d::Constant(half);
  ForCentresIn(world, a.cwiseMin(b) - pad, a.cwiseMax(b) + pad, [&](const Eigen::Vector2i& cell, const Eigen::Vector2d& p) {
    const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    if ((a + t * ab - p).squaredNorm() <= half * half) world.Set(cell, value);
  });
}

void FillPolygon(World& world, const std::vector<Eigen::Vector2d>& polygon, WorldCell value) {
  if (polygon.size() < 3) return;
  Eigen::Vector2d lo = polygon.front(), hi = polygon.front();
  for (const auto& v : polygon) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  ForCentresIn(world, lo, hi, [&](const Eigen::Vector2i& cell, const Eigen::Vector2d& p) {
    bool inside = false;
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
      const Eigen::Vector2d& u = polygon[i];
      const Eigen::Vector2d& v = polygon[j];
      if ((u.y() > p.y()) != (v.y() > p.y()) && p.x() < (v.x() - u.x()) * (p.y() - u.y()) / (v.y() - u.y()) + u.x()) {
        inside = !inside;
      }
    }
    if (inside) world.Set(cell, value);
  });
}

}  // namespace pslam
