#pragma once
// Beam-endpoint likelihood (a likelihood field computed on the fly): each endpoint scores a
// Gaussian of its distance to the nearest occupied cell within a small window.
//
// P-SLAM splits the observation (paper eq. 13): z^e, the endpoints on or near the explored map, and
// z^u, the endpoints in unexplored space that a hypothesis covers. z^e is scored against the map
// (S1 of eq. 22), z^u against the hypothesis map with the same sensor model (S2). Endpoints in
// unexplored space with no hypothesis score like an endpoint far from any wall, so that a pose is
// never rewarded for pushing its endpoints out of the map.
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
  // A wall explains an endpoint only if the cell in front of it, toward the sensor, is not
  // occupied too: a beam cannot have crossed a wall to end behind it. This keeps a map with a
  // doubled wall (a misclosed loop) from scoring better than a consistent one.
  bool free_space_check = true;
};

struct ScanLikelihood {
  double explored_log_likelihood = 0.0;    // S1: over z^e
  double hypothesis_log_likelihood = 0.0;  // S2: over z^u, against the hypothesis map
  double miss_log_likelihood = 0.0;        // the score of one endpoint far from any wall
  int explored_points = 0;                 // |z^e|
  int unexplored_points = 0;               // endpoints in unexplored space, z^u included
  int hypothesis_points = 0;               // |z^u|: unexplored endpoints inside a hypothesis
  int hypothesis_hits = 0;                 // |h ∩ z^u|: of those, the ones a predicted wall explains

  // Hit ratio of eq. 23; 0 when no endpoint fell inside a hypothesis.
  double hit_ratio() const { return hypothesis_points ? static_cast<double>(hypothesis_hits) / hypothesis_points : 0.0; }
  // log S1 (+ log S2 when the prediction is used); every other endpoint scores as a miss.
  double Total(bool use_hypothesis) const {
    const int scored_as_miss = unexplored_points - (use_hypothesis ? hypothesis_points : 0);
    return explored_log_likelihood + (use_hypothesis ? hypothesis_log_likelihood : 0.0) +
           scored_as_miss * miss_log_likelihood;
  }
};

ScanLikelihood ComputeScanLikelihood(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points_in_robot,
                                     const Pose2D& pose, const LikelihoodOptions& options,
                                     const OccupancyGrid* hypothesis = nullptr);

}  // namespace pslam
