#pragma once
// The rigid motion that lays a built map best onto a reference map (the simulator's true world, a
// floor plan). A map can be right wall for wall and still sit a few centimetres off, or a few
// milliradians turned, as a whole: a pose error the filter made while mapping new ground carries
// into all it maps from there, and later visits map the older parts again at that pose. Scored
// in the world's frame, that one offset counts against every wall.
// Scored after this alignment, Psi says how consistent the map is, and the alignment how far its
// frame moved. Found as a loop closure is: the map's occupied cells, thinned into a cloud, placed
// on the reference by the branch-and-bound correlative search.
#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/map_raster.hpp"

namespace pslam {

struct MapAlignmentOptions {
  double linear_window = 0.5;    // metres each way
  double angular_window = 0.05;  // radians each way
  double cloud_spacing = 0.1;    // metres between the occupied cells kept in the cloud
  CellStateThresholds states;    // what counts as an occupied cell
};

struct MapAlignment {
  Pose2D move;                // built map frame -> reference frame
  double centre_shift = 0.0;  // metres the middle of the built map's known area moves
  double psi = 0.0;           // BuiltMapSimilarity of the map as it lies
  double laid_psi = 0.0;      // ... and moved by 'move': never below psi
};

// The search's pose, its refinement and the identity are each scored by Psi, and the best is
// kept: the search's own score (points on walls) and Psi (walls matched both ways, on cells a
// move resamples) need not agree by a few hundredths, and a map already in place stays there.
// Throws std::invalid_argument if the maps' resolutions differ.
MapAlignment AlignMap(const OccupancyGrid& built, const OccupancyGrid& reference, const MapAlignmentOptions& options = {});

}  // namespace pslam
