#pragma once
// Every tunable of the particle filter, with its default, in one place.
#include <cstdint>

#include "pslam/filter/motion_model.hpp"
#include "pslam/grid/scan_inserter.hpp"
#include "pslam/matching/scan_likelihood.hpp"
#include "pslam/matching/scan_matcher.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {

struct RbpfOptions {
  int particles = 30;
  std::uint64_t seed = 1;
  double resolution = 0.05;           // metres per cell
  Pose2D initial_pose;                // pose of the first scan in the map frame
  // The filter updates once the tracked motion since the last update exceeds either threshold;
  // scans in between are tracked against the best map only (stabilised odometry).
  double linear_update = 0.25;        // metres
  double angular_update = 0.2;        // radians
  double resample_threshold = 0.5;    // resample when N_eff < threshold * N
  // Scan log-likelihoods are divided by this before they enter the weights: beams are not
  // independent, and treating them as such makes the filter overconfident.
  double likelihood_temperature = 6.0;
  int threads = 0;                    // worker threads for particle updates; 0: all cores

  ScanPointsOptions points{.max_usable_range = 20.0, .no_return_free_range = 0.0, .min_point_spacing = 0.03};
  ScanInsertOptions insert;
  ScanMatchOptions tracking_match{.coarsest_level = 2};
  ScanMatchOptions particle_match{.coarsest_level = 1};
  LikelihoodOptions likelihood;
  MotionNoise motion{.rotation_per_rotation = 0.05,
                     .rotation_per_translation = 0.02,
                     .translation_per_translation = 0.03,
                     .translation_per_rotation = 0.01};
};

}  // namespace pslam
