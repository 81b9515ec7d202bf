#pragma once
// Rao-Blackwellized particle filter for grid SLAM (paper section IV-B): each particle carries a
// pose, a map and a weight. Every scan is first tracked against the best particle's map (scan
// matching stabilises the raw odometry, as the paper does); once the robot has moved far enough,
// every particle samples the stabilised motion, refines it against its own map, is weighed by the
// scan likelihood, and the set is resampled when N_eff falls low. Then the scan is inserted.
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "pslam/common/parallel_for.hpp"
#include "pslam/filter/odometry_calibration.hpp"
#include "pslam/filter/rbpf_options.hpp"
#include "pslam/graph/loop_closure.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam {

// A particle's trajectory at its updates. Nodes are shared between particles that descend from the
// same ancestor, so resampling copies a pointer, not a history.
struct TrajectoryNode {
  Pose2D pose;
  int scan_index = 0;
  std::shared_ptr<const TrajectoryNode> parent;
};

struct Particle {
  Pose2D pose;                       // at the last update
  double log_weight = 0.0;           // since the last resampling
  OccupancyGrid map;
  OccupancyGrid hypothesis;          // predicted cells not yet observed, in this particle's frame
  std::shared_ptr<const TrajectoryNode> node;
  // Per hypothesis added (in order), the move of its cells from the best particle's frame at that
  // time into this particle's (eq. 20); inherited through resampling like the map.
  std::vector<Pose2D> hypothesis_frames;
};

// A predicted cell in the best particle's map frame.
struct PredictedCell {
  Eigen::Vector2i cell;
  bool occupied = false;
};

// How the hypotheses took part in one filter update.
struct PredictionUse {
  bool used = false;                 // S2 entered the weights
  bool measured = false;             // some particle had enough endpoints in hypotheses for a hit ratio
  int hypothesis_points = 0;         // |z^u| of the best particle
  double best_hit_ratio = 0.0;       // the highest hit ratio (eq. 23) over the particles
  double mean_hit_ratio = 0.0;       // over particles that had endpoints in hypotheses
};

struct RbpfStep {
  bool updated = false;              // the particles were moved, weighed and the scan inserted
  bool resampled = false;
  double neff = 0.0;                 // effective sample size after the update
  PredictionUse prediction;
  int best = 0;                      // index of the best particle
  Pose2D pose;                       // best estimate of the robot pose at this scan
  double tracking_score = 0.0;       // mean map evidence at the endpoints after tracking, in [0, 1]; 0 at the first scan
  // A loop closure corrected the past: every map was re-rendered, and the map around the robot
  // moved by `correction` (new frame from old, near the robot).
  bool loop_corrected = false;
  Pose2D correction;
};

struct RbpfStats {
  int scans = 0;
  int updates = 0;
  int resamplings = 0;
  double neff = 0.0;
  int updates_with_hypothesis_points = 0;  // updates where some endpoint fell in a hypothesis
  int updates_using_predictions = 0;       // ... and the hypotheses entered the weights
};

class Rbpf {
 public:
  explicit Rbpf(const RbpfOptions& options);

  RbpfStep AddScan(const LaserScan& scan);
  // Applies the loop closures still waiting for an optimisation (at the end of a log); returns
  // the correction (as RbpfStep::correction) when the maps and trajectory changed.
  std::optional<Pose2D> FlushLoopClosure();

  const std::vector<Particle>& particles() const { return particles_; }
  int best_index() const { return best_; }
  const Particle& best() const { return particles_[static_cast<std::size_t>(best_)]; }
  // Bytes of every particle's map and hypothesis grid, each shared tile counted once.
  double MapBytes() const;
  // Writes the particles' grids refused for their GridLimits (the most of any one grid).
  std::uint64_t RefusedMapWrites() const;
  const RbpfStats& stats() const { return stats_; }
  const OdometryCalibration& odometry_calibration() const { return calibration_; }
  // Null when loop closure is off.
  const LoopCloser* loop_closer() const { return loop_closer_.get(); }
  const RbpfOptions& options() const { return options_; }
  // Normalised weights of the particles.
  std::vector<double> Weights() const;

  // The hypothesis model H of eq. 20: adds predicted cells, given in the best particle's frame, to
  // every particle's hypothesis map, moved by that particle's pose relative to the best one.
  // Cells a particle has already observed are left out: hypotheses only cover unexplored space.
  // Returns the hypothesis's index into Particle::hypothesis_frames (-1 before the first scan).
  int AddHypothesis(const std::vector<PredictedCell>& cells);
  // Takes cells of hypothesis 'index' (in the best particle's frame when it was added, moved by
  // every loop correction since) out of every particle's hypothesis map again (a refuted or
  // expired hypothesis).
  void RemoveHypothesis(int index, const std::vector<PredictedCell>& cells);

  // The best particle's pose at every scan added so far: its own poses at updates, and in between
  // the tracked motion, bent so that it meets the next update exactly.
  std::vector<Pose2D> Trajectory() const;
  // Indices of the scans at which the best particle's lineage was updated (the processed scans).
  std::vector<int> UpdateScanIndices() const;

 private:
  void Initialize(const LaserScan& scan);
  void InsertScan(const ScanPoints& points, const Pose2D& pose, OccupancyGrid& map, OccupancyGrid* hypothesis) const;
  PredictionUse UpdateParticles(const Pose2D& motion, const std::vector<Eigen::Vector2f>& hits);
  void SelectBest();
  // Moves every particle onto the corrected trajectory and map; returns the move near the robot.
  Pose2D ApplyCorrection(const LoopClosureCorrection& correction);
  void Resample(const std::vector<double>& weights);
  // Calls visit(particle, cell, predicted) in parallel for every particle and every predicted
  // cell, 'cell' being that cell moved into the particle's frame by hypothesis_frames[index].
  void ForEachCellInParticles(int index, const std::vector<PredictedCell>& cells,
                              const std::function<void(Particle&, const Eigen::Vector2i&, const PredictedCell&)>& visit);

  RbpfOptions options_;
  ScanInserter inserter_;
  // Extend mode: the prior as the particles started from it, for ForgetPriorFloorBehindNewSurfaces.
  std::shared_ptr<const OccupancyGrid> start_map_;
  ThreadPool pool_;
  std::vector<Particle> particles_;
  int best_ = 0;
  RbpfStats stats_;
  Pose2D odometry_at_update_;
  OdometryCalibration calibration_;
  std::vector<Pose2D> tracked_;      // per scan: pose relative to the tracked particle's last update
  Pose2D last_pose_;
  bool has_hypotheses_ = false;
  std::unique_ptr<LoopCloser> loop_closer_;
};

}  // namespace pslam
