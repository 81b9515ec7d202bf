#pragma once
// A map from an earlier session as the start of a new one (extend mode). Its cells carry the
// confidence of many past scans; kept as they are, a wall that has since moved would need as many
// scans again to fade, and the new map would show both the old wall and the new one. Capping the
// prior's log-odds lets a few scans of the present overwrite a changed area.
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

// 'prior' with every known cell's log-odds clamped to +-logodds(max_probability). Tiles with no
// cell beyond the cap stay shared with 'prior'. max_probability >= 1 (or <= 0.5) returns the prior
// unchanged: no cap.
OccupancyGrid CapPriorConfidence(const OccupancyGrid& prior, double max_probability);

}  // namespace pslam
