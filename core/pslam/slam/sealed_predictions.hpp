#pragma once
// A predicted room needs a way in.
//
// A hypothesis copies a region of the map around its target, rooms and doors alike. Where the
// copy lands a room on space the robot has already seen closed (a solid corner of the building
// behind a corridor wall, a desk whose faces the robot has mapped), the room's door falls on an
// observed wall and is not predicted, or is withdrawn once seen (local_refutation.hpp): its floor
// is then cut off from all the floor the robot has seen. Such floor is no prediction of anything
// the robot could reach, and it is taken out of the hypothesis with the walls that bound only it.
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/hypothesis.hpp"
#include "pslam/predict/map_raster.hpp"

namespace pslam {

// Takes out of 'h' (its cells and undecided cells) the predicted floor that no 4-connected path
// through predicted floor and the map's observed free or undecided cells joins to a free cell of
// 'map', never through a wall, observed or predicted, nor through space neither knows; and the
// predicted walls with none of the joined cells within 'wall_reach_cells'. Returns them.
std::vector<HypothesisCell> TakeSealedOff(Hypothesis& h, const OccupancyGrid& map, const CellClassifier& classify,
                                          int wall_reach_cells = 2);

}  // namespace pslam
