#pragma once
// Extend mode: the prior map's floor behind a surface that has appeared since. When the laser hits
// a cell the earlier session mapped as floor, something now stands there, and the prior's floor
// behind that face, which the robot cannot see, is as likely part of it as floor. Left free, a
// crate or a moved wall would be mapped as a face with floor behind it, wherever the truth is solid.
// So the cells behind each such hit that still hold the prior's value (no scan of this session has
// touched them) are forgotten, up to a depth, and stay unknown until the robot sees them.
#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {

// 'prior' is the map the session started from, as its particles got it (CapPriorConfidence), on
// the same lattice as 'map'. For every hit of 'points' at 'pose' whose cell the prior has as free,
// and not within two cells of one of its walls, walks on along the beam for up to 'depth' metres:
// forgets the cells that still hold the prior's free value, passes cells this session has as
// occupied or already forgotten, and stops at the first other cell (one the prior has as wall or
// unknown, or floor seen now). Returns the cells forgotten.
int ForgetPriorFloorBehindNewSurfaces(const ScanPoints& points, const Pose2D& pose, const OccupancyGrid& prior,
                                      double depth, OccupancyGrid& map);

}  // namespace pslam
