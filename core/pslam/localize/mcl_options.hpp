#pragma once
// Every tunable of Monte Carlo localization, with its default. Names and defaults follow ROS AMCL
// where it has the same knob (min/max particles, kld_err, kld_z, update_min_d/a, recovery alphas,
// laser_likelihood_max_dist), so that settings carry over.
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "pslam/filter/motion_model.hpp"
#include "pslam/localize/place_recognizer.hpp"
#include "pslam/localize/scan_odometry.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {

// Likelihood-field sensor model (Thrun, Burgard, Fox, Probabilistic Robotics, 6.4): an endpoint
// at distance d from the nearest occupied cell scores z_hit * exp(-d^2 / 2 sigma^2) + z_rand.
// Distances are capped at max_distance; endpoints off the map score as that far.
struct LikelihoodFieldOptions {
  double sigma = 0.15;               // m
  double z_hit = 0.9;
  double z_rand = 0.1;               // beams the map does not explain (people, clutter)
  double max_distance = 2.0;         // m
  double occupied_probability = 0.65;  // a map cell at or above this is an obstacle (map_server's threshold)
  int max_beams = 60;                // endpoints scored per scan, evenly spread over the returns
  // Scan log-likelihoods are divided by this: beams are not independent (as in RbpfOptions).
  double temperature = 5.0;
  // Distances to the face of the nearest occupied cell instead of its centre. Off by default: it
  // brought simulated tracking from 0.048 / 0.055 / 0.063 m to 0.046 / 0.048 / 0.057 m (office,
  // maze, irregular) and Intel from 2.21 to 1.79 m, but recovery after a kidnapping fell from 4 of
  // 5 runs to 1, and ACES's global start from 0.34 to 1.02 m RPE.
  bool face_distance = false;
  // An endpoint where the map saw nothing that lands this close to an obstacle is explained by it
  // and not added (MclOptions::fill_unknown). In the office with its east half forgotten, adding
  // every endpoint thickened walls into bands the estimate drifted across: 0.90 m mean error;
  // 0.36 m at 0.075, 0.19 m at 0.15, 0.20 m at 0.3.
  double fill_clearance = 0.15;  // m
};

struct MclOptions {
  // KLD sampling (Fox, IJRR 2003): after each resampling the particle count is the smallest that
  // keeps the KL divergence between the sample-based and the true posterior below kld_err, given
  // how many histogram bins the posterior occupies. kld_z is the standard normal quantile of the
  // confidence, used as given as AMCL does (its default 0.99 is the quantile, not the confidence).
  // Global localization starts with max_particles: the more, the likelier one lands near the
  // true pose before the cloud settles on a look-alike place (in the irregular world, 5000, AMCL's
  // default, converged in none of 5 runs, 20000 in 4; KLD shrinks the set within a few updates).
  int min_particles = 500;
  int max_particles = 20000;
  double kld_err = 0.01;
  double kld_z = 0.99;
  double bin_size_xy = 0.5;                          // m
  double bin_size_theta = 10.0 * std::numbers::pi / 180.0;  // rad

  // The filter updates once odometry moved by either threshold since the last update.
  double update_min_d = 0.2;                         // m
  double update_min_a = std::numbers::pi / 6.0;      // rad
  double resample_threshold = 0.5;                   // resample when N_eff < threshold * N

  // Augmented MCL (Probabilistic Robotics, 8.3.5): short- and long-term averages of the
  // measurement likelihood; when the short one falls below the long one, that share of the
  // resampled particles is drawn at random over the free space (recovery from kidnapping).
  // 0 / 0 turns injection off.
  double recovery_alpha_slow = 0.001;
  double recovery_alpha_fast = 0.1;
  // Injection starts only once 1 - w_fast / w_slow exceeds this. AMCL injects at any drop (and
  // ships with recovery off); localizing the second half of the ACES log on a map of its first
  // half, injection at drops above 0.5 let random particles in look-alike corridors win where the
  // robot saw what the map lacks, and the estimate jumped 20-40 m away for good. Above 0.7 it did
  // not, while a kidnapping in the simulated worlds still drops the fit further.
  double recovery_min_drop = 0.7;

  // Raw wheel odometry is far noisier than the scan-matched motion the mapping filter samples.
  MotionNoise motion{.rotation_per_rotation = 0.1,
                     .rotation_per_translation = 0.05,
                     .translation_per_translation = 0.1,
                     .translation_per_rotation = 0.02};
  LikelihoodFieldOptions likelihood;
  ScanPointsOptions points{.max_usable_range = 20.0, .no_return_free_range = 0.0, .min_point_spacing = 0.0};

  // "Localized": the heaviest cluster of particles holds at least this share of the weight and
  // spreads less than these (standard deviations).
  double localized_weight = 0.8;
  double localized_position_std = 0.15;              // m, along the cluster's widest direction
  double localized_heading_std = 5.0 * std::numbers::pi / 180.0;  // rad

  // Refinement of the reported estimate once localized (LikelihoodField::Refine): at every scan,
  // the pose near the cloud's estimate that best explains the scan, with the cloud's spread as a
  // prior and endpoints behind a wall's seen face scoring as misses. The report is the last one
  // moved by odometry and pulled toward that fit by refine_gain: a fit per scan alone is accurate
  // on an exact map but jitters on a real one, which relative errors punish (ACES second half:
  // seed 1: 0.061 m RPE at gain 1, 0.047 at 0.1, 0.048 unrefined; the second halves of ACES,
  // Intel and FR079 on their first halves' maps, seeds 1-3: 0.039 / 0.022 / 0.036 m at 0.1,
  // 0.038 / 0.018 / 0.032 m at 0.03; simulated tracking 3-5 mm worse on the worlds' own maps).
  bool refine = true;
  double refine_gain = 0.03;                         // 1: each scan's fit as it is
  int refine_max_points = 90;                        // endpoints used, evenly spread over the returns
  double refine_max_shift = 0.12;                    // m: the cloud is tighter than this once localized
  double refine_max_turn = 0.1;                      // rad

  // Once localized, the endpoints of each update that land in cells the map never observed, within
  // its bounds, join the likelihood field as obstacles at the reported pose: the map is extended
  // by what the robot sees, as Cartographer's pure localization keeps local submaps.
  // Without it, those endpoints score by their distance to the map's nearest wall and pull the
  // cloud onto it: the second halves of ACES, Intel and FR079 on their first halves' maps went
  // from 0.051 / 0.184 / 1.61 m RPE to 0.040 / 0.019 / 0.032 m (seed 1).
  bool fill_unknown = true;
  // ... but not while fewer than this share of the endpoints the map can check agree with it, when
  // there are at least fill_min_checked of them. An endpoint on a cell the map observed agrees
  // when it lies within fill_clearance of an obstacle; one whose beam crossed an obstacle
  // disagrees, and is never added: a kidnapped robot whose fit has not dropped yet would draw the
  // wrong place's walls where the map saw nothing and then fit them. Without this share (0), ACES
  // seed 1 went from 0.040 to 0.044 m.
  double fill_min_agreement = 0.3;
  int fill_min_checked = 10;

  // Odometry corrected by matching each scan against the last few (scan_odometry.hpp), in place of
  // the wheels' own. On by default: on the ACES log it brought localization from 0.0556 to
  // 0.0479 m RPE at seeds 1-5, and the place recognizer's cloud bends less; in the simulated
  // worlds tracking moves by under a centimetre either way, at twice the CPU (still about half
  // the mapping filter's).
  ScanOdometryOptions scan_odometry;
  // Global localization searches the whole map for the cloud of the last metres' scans
  // (place_recognizer.hpp) and starts tracking where that place is unique; while look-alike places
  // remain, the localizer does not report itself localized, whatever its particles agree on.
  PlaceRecognitionOptions place;
  // When the search finds the best place and a look-alike, the particles are drawn around both
  // (once per search for the place) and the scans that follow weigh them, so the estimate is most
  // often at the right place long before the search tells it apart; localized is still reported
  // only once the search finds a place without a rival. On the office map an exploration built,
  // the estimate was within 0.2 m after 12 m of travel instead of 35 (docs/localization.md).
  bool track_look_alikes = true;
  std::uint64_t seed = 1;
};

// Sets one option by its dotted name (e.g. "min_particles", "likelihood.sigma") from text. Returns
// an empty string on success, or what is wrong; unknown names are rejected.
std::string SetMclOption(MclOptions& options, const std::string& name, const std::string& value);

// Names of every option SetMclOption accepts, for help texts.
std::vector<std::string> MclOptionNames();

// What is inconsistent in the options (e.g. min_particles > max_particles), or empty.
std::string ValidateMclOptions(const MclOptions& options);

}  // namespace pslam
