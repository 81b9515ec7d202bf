#pragma once
// A submap: the scans of a run of consecutive nodes rendered into a grid in the frame of its first
// node. It moves as one rigid piece when the pose graph is optimised.
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

struct Submap {
  int first_node = 0;
  int last_node = 0;                          // inclusive
  OccupancyGrid grid;                         // in the first node's frame
  bool finished = false;

  int nodes() const { return last_node - first_node + 1; }
};

}  // namespace pslam
