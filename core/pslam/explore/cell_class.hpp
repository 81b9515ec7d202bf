#pragma once
// How exploration reads the robot's built map: each cell is free, occupied or unknown.
//
// Free means p < 0.4 and occupied p > 0.6 (defaults). With the default ScanInsertOptions a single
// miss gives p = 0.40 and a single hit p = 0.70: a cell must be seen empty twice before the robot
// plans through it, while one hit already makes an obstacle. Cells in between are still uncertain
// and count as unknown, like cells never observed: neither safe to cross nor walls to keep clear of.
#include <Eigen/Core>

#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

enum class CellClass : unsigned char { kFree, kOccupied, kUnknown };

struct CellClassOptions {
  float free_below = 0.4f;       // probability
  float occupied_above = 0.6f;   // probability
};

inline CellClass Classify(const OccupancyGrid& grid, const Eigen::Vector2i& c, const CellClassOptions& o) {
  const OccupancyGrid::Cell v = grid.At(c.x(), c.y());
  if (v == OccupancyGrid::kUnknown) return CellClass::kUnknown;
  const float p = CellProbability(v);
  if (p < o.free_below) return CellClass::kFree;
  if (p > o.occupied_above) return CellClass::kOccupied;
  return CellClass::kUnknown;
}

}  // namespace pslam
