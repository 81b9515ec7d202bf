#pragma once
// Monte Carlo localization on a fixed map (Dellaert, Fox, Burgard and Thrun, ICRA 1999), as ROS
// AMCL does it: particles move with the odometry motion model and sampled noise, are weighed by
// the likelihood field of the map, and are resampled (low variance) when N_eff falls. The count
// adapts by KLD sampling between min and max particles; augmented MCL injects random particles
// over the free space when the measurements suddenly fit worse than they used to, which recovers
// from kidnapping. Without a pose (or after such a drop) the map is searched for the last metres
// of scans (place_recognizer.hpp), and the robot counts as localized only once one place explains
// them. Deterministic for a seed.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/localize/likelihood_field.hpp"
#include "pslam/localize/mcl_options.hpp"
#include "pslam/localize/particle_clusters.hpp"
#include "pslam/localize/place_recognizer.hpp"
#include "pslam/localize/scan_odometry.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam {

struct MclUpdate {
  bool updated = false;          // the particles moved and were weighed at this scan
  bool resampled = false;
  int particles = 0;             // after this scan
  int injected = 0;              // random particles drawn at this resampling
  double effective_sample_size = 0.0;  // before resampling
  double injection_probability = 0.0;  // 1 - w_fast / w_slow, at least 0
  // The mean of the heaviest cluster, moved on by odometry since the update; with
  // MclOptions::refine, once localized, refined against the map at every scan.
  Pose2D estimate;
  ParticleCluster cluster;       // the heaviest cluster at the last update
  int clusters = 0;
  // The heaviest cluster is heavy and tight enough (MclOptions), and global localization, if it
  // is still searching, found no look-alike place.
  bool localized = false;
  bool searching = false;        // global localization is still searching the map for the place
  PlaceMatch place;              // its last search (outcome kNone before the first)
};

struct MclStats {
  int scans = 0;
  int updates = 0;
  int resamplings = 0;
  long long injected = 0;
  int min_particles_seen = 0;
  int max_particles_seen = 0;
};

class MonteCarloLocalizer {
 public:
  // Throws std::invalid_argument for invalid options, or a map without obstacles or free cells.
  MonteCarloLocalizer(const OccupancyGrid& map, const MclOptions& options);

  // Starts from a known pose: max_particles drawn from a Gaussian around it (covariance over x, y,
  // theta, positive semi-definite, else std::invalid_argument).
  void SetPose(const Pose2D& mean, const Eigen::Matrix3d& covariance);
  // Global localization: max_particles spread uniformly over the map's free cells and headings.
  // The first scan starts this when neither was called.
  void StartGlobal();

  // One scan, with the robot's raw odometry at its time in scan.odometry.
  MclUpdate AddScan(const LaserScan& scan);

  const std::vector<Pose2D>& particles() const { return poses_; }
  std::vector<double> weights() const;  // normalised
  const MclUpdate& last() const { return last_; }
  const MclStats& stats() const { return stats_; }
  int unmapped_obstacles() const { return field_.added_obstacles(); }  // cells added by fill_unknown
  std::size_t free_cells() const { return free_cells_.size(); }
  const MclOptions& options() const { return options_; }

 private:
  Pose2D RandomFreePose(std::mt19937_64& rng) const;
  void Reset(std::vector<Pose2D> poses);
  // max_particles poses, the i-th drawn around centres[i % size] as root * N(0, I) (kStart stream).
  std::vector<Pose2D> DrawAround(const std::vector<Pose2D>& centres, const Eigen::Matrix3d& root);
  void Weigh(const std::vector<Eigen::Vector2f>& points);
  void Resample();
  void Summarize();
  // Both take the scan's endpoints in the robot frame.
  void RefineEstimate(const std::vector<Eigen::Vector2f>& hits, const Pose2D& odometry);
  void SearchPlace(const std::vector<Eigen::Vector2f>& hits, const Pose2D& odometry);
  void DrawAroundLookAlikes(const PlaceMatch& match, const Pose2D& odometry);
  void FillUnknown(const std::vector<Eigen::Vector2f>& hits);  // MclOptions::fill_unknown

  MclOptions options_;
  LikelihoodField field_;
  ScanOdometry scan_odometry_;
  std::optional<PlaceRecognizer> places_;  // with MclOptions::place.enabled
  double resolution_;
  std::vector<Eigen::Vector2i> free_cells_;
  std::vector<Pose2D> poses_;
  std::vector<double> log_weights_;
  bool initialized_ = false;
  bool have_odometry_ = false;
  bool force_update_ = false;      // weigh at the next scan even without motion (a fresh start)
  Pose2D update_odometry_;         // odometry at the last update
  std::uint64_t step_ = 0;         // updates and starts so far: the random stream index
  long long averaged_ = 0;         // samples in the recovery averages since the last start
  double log_w_slow_ = 0.0, log_w_fast_ = 0.0;
  std::optional<Pose2D> report_;   // the last refined report, and the odometry it was made at
  Pose2D report_odometry_;
  MclUpdate last_;
  MclStats stats_;
  bool look_alikes_drawn_ = false;  // the particles stand around a place and its look-alike
};

}  // namespace pslam
