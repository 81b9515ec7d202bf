#pragma once
// The part of a true world a laser could ever map from inside it: the free cells the robot can
// reach and the obstacle cells that touch them (the faces of walls and blocks). The inside of a
// solid block, a sealed room and the space outside stay unknown: no run can see them, so a
// prediction there can be neither right nor wrong by anything the robot will observe.
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

// 'reachable' as ReachableFreeCells gives it (free where reachable, unknown elsewhere). Returns a
// grid on the world's lattice: free on the reachable cells, occupied on obstacle cells 8-adjacent
// to one of them, unknown everywhere else.
OccupancyGrid ObservableTruth(const World& world, const OccupancyGrid& reachable);

}  // namespace pslam
