#pragma once
// Rigid motion of a grid's known cells (nearest cell), for layers that must follow a corrected map.
#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

// A grid holding each known cell of `grid` at the cell nearest to `move` applied to its centre.
OccupancyGrid TransformGrid(const OccupancyGrid& grid, const Pose2D& move);

}  // namespace pslam
