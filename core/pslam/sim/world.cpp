#include "pslam/sim/world.hpp"

#include <algorithm>
#include <cmath>

#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

OccupancyGrid::Cell MilliLogOdds(double p) {
  return static_cast<OccupancyGrid::Cell>(std::lround(std::log(p / (1.0 - p)) / OccupancyGrid::kLogOddsPerUnit));
}

}  // namespace

World::World(double resolution, const CellBox& bounds, WorldCell fill)
    : resolution_(resolution),
      bounds_(bounds),
      cells_(static_cast<std::size_t>(bounds.width()) * static_cast<std::size_t>(bounds.height()), fill) {}

World World::FromGrid(const OccupancyGrid& grid) {
  World world(grid.resolution(), grid.KnownBounds(), WorldCell::kUnknown);
  const CellBox& b = world.bounds_;
  for (int y = b.min.y(); y <= b.max.y(); ++y) {
    for (int x = b.min.x(); x <= b.max.x(); ++x) {
      if (!grid.IsKnown(x, y)) continue;
      const float p = grid.Probability(x, y);
      if (p > 0.5f) world.Set({x, y}, WorldCell::kOccupied);
      else if (p < 0.5f) world.Set({x, y}, WorldCell::kFree);
    }
  }
  return world;
}

bool World::IsDiscFree(const Eigen::Vector2d& centre, double radius) const {
  // Every cell whose square comes closer to the centre than 'radius' must be free: exact for a
  // disc against axis-aligned squares, so a 0.25 m robot fits through a 0.5 m gap and no less.
  const Eigen::Vector2i lo = WorldToCell(centre - Eigen::Vector2d::Constant(radius));
  const Eigen::Vector2i hi = WorldToCell(centre + Eigen::Vector2d::Constant(radius));
  const double r2 = radius * radius;
  for (int y = lo.y(); y <= hi.y(); ++y) {
    const double y0 = y * resolution_, y1 = y0 + resolution_;
    const double dy = centre.y() < y0 ? y0 - centre.y() : (centre.y() > y1 ? centre.y() - y1 : 0.0);
    for (int x = lo.x(); x <= hi.x(); ++x) {
      const double x0 = x * resolution_, x1 = x0 + resolution_;
      const double dx = centre.x() < x0 ? x0 - centre.x() : (centre.x() > x1 ? centre.x() - x1 : 0.0);
      if (dx * dx + dy * dy < r2 && !IsFree({x, y})) return false;
    }
  }
  return true;
}

std::size_t World::Count(WorldCell value) const {
  return static_cast<std::size_t>(std::count(cells_.begin(), cells_.end(), value));
}

OccupancyGrid World::ToGrid() const {
  OccupancyGrid grid(resolution_);
  const OccupancyGrid::Cell occupied = MilliLogOdds(kLoadedOccupiedProbability);
  const OccupancyGrid::Cell free = MilliLogOdds(kLoadedFreeProbability);
  for (int y = bounds_.min.y(); y <= bounds_.max.y(); ++y) {
    for (int x = bounds_.min.x(); x <= bounds_.max.x(); ++x) {
      const WorldCell c = cells_[Index({x, y})];
      if (c != WorldCell::kUnknown) grid.MutableAt(x, y) = c == WorldCell::kOccupied ? occupied : free;
    }
  }
  return grid;
}

World LoadWorld(const std::string& yaml_path) { return World::FromGrid(LoadMap(yaml_path)); }

}  // namespace pslam
