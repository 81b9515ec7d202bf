#pragma once
// Beam-endpoint likelihood (a likelihood field computed on the fly): each endpoint scores a
// Gaussian of its distance to the nearest occupied cell within a small window. Endpoints that land
// in unknown space, with no wall near, are counted separately: that is what splits an observation
// into its explored part z^e and unexplored part z^u (paper eq. 13).
#include <Eigen/Core>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

struct LikelihoodOptions {
  double sigma = 0.05;             // metres: spread of the endpoint error
  int window_cells = 2;            // search radius for the nearest occupied cell
  double occupied_probability = 0.6;
  int point_step = 2;              // score every n-th endpoint
};

struct ScanLikelihood {
  double log_likelihood = 0.0;     // over all scored endpoints
  int explored_points = 0;         // endpoints on or near observed cells
  int unexplored_points = 0;       // endpoints in unknown space with no wall near
};

ScanLikelihood ComputeScanLikelihood(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points_in_robot,
                                     const Pose2D& pose, const LikelihoodOptions& options);

}  // namespace pslam
