#pragma once
// Finds the tiles of a grid that changed since the last look, without comparing cells: a written
// tile either got a new pointer (copy on write) or a higher revision. The tracker keeps a copy of
// the grid it last saw; holding those tiles is what makes pointer comparison sound (a tile we still
// hold cannot be freed and its address reused), and it turns every later write to them into a
// copy, so a change always shows as a new pointer.
#include <Eigen/Core>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"

namespace pslam::server {

class TileTracker {
 public:
  // Tile indices of 'grid' that may differ from the grid of the previous call (every allocated
  // tile on the first call), including tiles the previous grid had and 'grid' lacks. Remembers
  // 'grid' (a cheap copy: tile pointers).
  std::vector<Eigen::Vector2i> Changed(const OccupancyGrid& grid);

 private:
  OccupancyGrid previous_;
  bool first_ = true;
};

}  // namespace pslam::server
