#pragma once
// Every tunable of the particle filter, with its default, in one place.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pslam/filter/motion_model.hpp"
#include "pslam/filter/odometry_calibration.hpp"
#include "pslam/graph/loop_closure_options.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/grid/scan_inserter.hpp"
#include "pslam/matching/scan_likelihood.hpp"
#include "pslam/matching/scan_matcher.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {

struct RbpfOptions {
  int particles = 30;
  std::uint64_t seed = 1;
  double resolution = 0.05;           // metres per cell
  GridLimits grid;                    // bounds of every particle's grids
  Pose2D initial_pose;                // pose of the first scan in the map frame
  // Extend mode: every particle's map starts as this map of an earlier session (its tiles shared
  // until a particle writes them), the first scan taken at initial_pose in its frame; null starts
  // from nothing. Its cells' confidence is capped at prior_max_probability (prior_map.hpp), so that
  // a few scans of a changed area overwrite it; >= 1 keeps the prior as it is.
  std::shared_ptr<const OccupancyGrid> prior_map;
  double prior_max_probability = 0.9;  // a wall then clears after 6 misses instead of 9
  // Behind a hit on the prior's floor (something new stands there), the prior's floor the session
  // has not seen yet is forgotten this deep (stale_prior.hpp); 0 keeps it.
  double prior_forget_depth = 1.0;  // metres
  // The filter updates once the tracked motion since the last update exceeds either threshold;
  // scans in between are tracked against the best map only (stabilised odometry).
  double linear_update = 0.25;        // metres
  double angular_update = 0.2;        // radians
  double resample_threshold = 0.5;    // resample when N_eff < threshold * N
  // Scan log-likelihoods are divided by this before they enter the weights: beams are not
  // independent, and treating them as such makes the filter overconfident.
  double likelihood_temperature = 6.0;
  int threads = 0;                    // worker threads for particle updates; 0: all cores

  // P-SLAM (paper eq. 21-23): weigh endpoints in unexplored space against the hypotheses.
  bool use_predictions = true;
  // Recovery: use the hypotheses in an update only if some particle's hit ratio (eq. 23) reaches
  // the threshold; otherwise they contradict what the robot sees and would mislead the weights.
  bool recovery = true;
  double hit_ratio_threshold = 0.5;
  int min_hypothesis_points = 5;      // fewer endpoints in hypotheses say too little to weigh by

  ScanPointsOptions points{.max_usable_range = 20.0, .no_return_free_range = 0.0, .min_point_spacing = 0.03};
  ScanInsertOptions insert;
  // Tracking starts from odometry alone and must also pull the pose back onto old structure when
  // the robot returns to it after a long excursion (the last loop of the Intel log): it matches
  // from 40 cm pooled cells down. Particles start from the tracked pose and need less.
  // Both keep odometry along a direction the scan barely constrains (degenerate_ratio): in a long
  // corridor the match otherwise slides, and every particle with it, since each is refined onto
  // the same optimum. On ACES at 10 particles, seed 9, the estimate fell 6 m behind the robot in
  // one corridor and the map doubled it (docs/loop-closure.md).
  ScanMatchOptions tracking_match{.coarsest_level = 3, .degenerate_ratio = 0.15, .hit_offsets = true};
  ScanMatchOptions particle_match{.coarsest_level = 1, .degenerate_ratio = 0.15, .hit_offsets = true};
  LikelihoodOptions likelihood;
  MotionNoise motion;
  // Scales the wheel odometry by what scan matching measured of it (odometry_calibration.hpp).
  OdometryCalibrationOptions odometry_calibration;
  // Loop closure over a pose graph of the best particle's updates (pslam/graph/loop_closure.hpp).
  LoopClosureOptions loop_closure;
};

}  // namespace pslam

namespace pslam {

// Sets one option by its dotted name (e.g. "motion.translation_per_translation", "linear_update")
// from text. Returns an empty string on success, or what is wrong: unknown names are rejected so
// that a typo never silently falls back to a default.
std::string SetRbpfOption(RbpfOptions& options, const std::string& name, const std::string& value);

// The scan matcher's degeneracy guard (ScanMatchOptions::degenerate_ratio) for both the tracking
// and the particle matches, as the simulated explorations and server sessions set it.
void SetDegenerateRatio(RbpfOptions& options, double ratio);

// The scan matcher's prior toward odometry (ScanMatchOptions::prior_translation_weight and
// prior_rotation_weight) for both the tracking and the particle matches: how far the wheels are
// trusted where the scan says little.
void SetMatchPrior(RbpfOptions& options, double translation_weight, double rotation_weight = 0.0);

// ScanMatchOptions::hit_offsets for both the tracking and the particle matches.
void SetHitOffsets(RbpfOptions& options, bool enabled);

// Names of every option SetRbpfOption accepts, for help texts.
std::vector<std::string> RbpfOptionNames();

}  // namespace pslam
