#pragma once
// P-SLAM (Chang et al., IEEE T-RO 2007): the particle filter plus the look-ahead mapping of
// Fig. 6. For every new exploration target T_k (not every replanning toward the same frontier, see
// PSlamOptions::new_target_distance_m) the structure predictor runs on its own thread over a
// snapshot of the best map (or of the merged map, PSlamOptions::predict_on_merged_map); an
// accepted hypothesis h_k goes into every particle's hypothesis map (H of eq. 20), weighs the
// particles through S2 (eq. 21-22, with the hit-ratio recovery of eq. 23), and gives way cell by
// cell to what the robot observes (V of eq. 20). Each hypothesis is judged once enough of it, with
// enough structure, has been seen: confirmed or refuted by Psi against the observation
// (hypothesis_judge.hpp), or expired if the robot never goes there. Only a refutation withdraws a
// hypothesis's coverage of unexplored space.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "pslam/filter/rbpf.hpp"
#include "pslam/predict/async_predictor.hpp"
#include "pslam/predict/hypothesis.hpp"
#include "pslam/slam/prediction_coverage.hpp"
#include "pslam/slam/pslam_options.hpp"

namespace pslam {

struct HypothesisEvent {
  int id = 0;
  double time = 0.0;
  Hypothesis::Status status = Hypothesis::Status::kPending;
};

struct PSlamStats {
  int targets = 0;                 // exploration targets set
  int new_targets = 0;             // of which far enough from the last to ask for a prediction
  int predictions_requested = 0;   // accepted by the predictor (it was not busy)
  int predictions_made = 0;        // finished, with or without a hypothesis
  int hypotheses = 0;              // accepted hypotheses
  int confirmed = 0, refuted = 0, expired = 0;
  double last_prediction_ms = 0.0;
  double max_prediction_ms = 0.0;
  PredictorStats outcomes;         // why predictions did or did not yield a hypothesis
};

struct PSlamStep {
  RbpfStep filter;
  std::vector<int> changed_hypotheses;  // ids added or whose status, cells or scores changed
};

class PSlam {
 public:
  explicit PSlam(const PSlamOptions& options);

  PSlamStep AddScan(const LaserScan& scan);
  // Sets the exploration target T_k, a cell of the best map; a new target starts a prediction.
  void SetTarget(const Eigen::Vector2i& cell, double time);
  std::optional<Eigen::Vector2i> target() const { return target_; }

  const Rbpf& filter() const { return filter_; }
  const PSlamOptions& options() const { return options_; }
  const std::vector<Hypothesis>& hypotheses() const { return hypotheses_; }
  const std::vector<HypothesisEvent>& history() const { return history_; }
  PSlamStats stats() const;
  // Whether an unknown or undecided cell of the best map is covered by a hypothesis that was not
  // refuted (pending, confirmed or expired): what skip-predicted exploration asks.
  bool IsCovered(const Eigen::Vector2i& cell) const;
  // Whether such a hypothesis predicts a wall there: the space behind it is not the frontier's.
  bool IsPredictedWall(const Eigen::Vector2i& cell) const;
  // The covered cells and predicted walls, for planning on a snapshot off this thread (copying
  // shares the tiles).
  const PredictionCoverage& coverage() const { return coverage_; }
  // The same over the settled hypotheses only: confirmed, or expired (unobserved for expiry_s with
  // nothing against them). Built on each call.
  PredictionCoverage SettledCoverage() const;
  // The best map with the cells of the hypotheses that were not refuted written into unknown
  // cells, and into undecided ones (Hypothesis::undecided_cells); only of those confirmed or with
  // Psi >= min_psi (what the predictor reads, PSlamOptions::predict_from_psi).
  OccupancyGrid MergedMap(double min_psi = 0.0) const;
  // Psi of every hypothesis against the current best map, over all of its original cells observed
  // so far (psi_observed), for reports at the end of a run.
  void ScoreHypotheses();
  // Waits for a running prediction to finish and takes its result (end of a log, tests).
  void FlushPredictions();
  // Applies loop closures still waiting for an optimisation (end of a log); true if the maps changed.
  bool FlushLoopClosure();

 private:
  void TakePrediction(double time);
  void JudgeHypotheses(const RbpfStep& step, double time, std::vector<int>& changed);
  void SetStatus(std::size_t index, Hypothesis::Status status, double time);
  // Withdraws the cells of hypothesis i near where 'seen' (its cells just observed) contradicts it
  // (HypothesisJudgeOptions::local_refutation_radius_m) from it, the coverage and the weights.
  void WithdrawAroundContradictions(std::size_t i, const std::vector<HypothesisCell>& seen);
  void MaybeRetargetFromHeading(double time);
  // Moves the hypotheses, coverage and targets with a loop-corrected map; `changed` gets their ids.
  void FollowCorrection(const Pose2D& move, std::vector<int>* changed);

  PSlamOptions options_;
  Rbpf filter_;
  std::unique_ptr<AsyncPredictor> predictor_;
  std::vector<Hypothesis> hypotheses_;   // cells shrink as they are observed
  std::vector<Hypothesis> originals_;    // as generated, for Psi against the observation
  std::vector<double> last_observed_;    // time a cell of each hypothesis was last observed
  std::vector<int> filter_index_;        // each hypothesis's index in the filter's hypothesis_frames
  std::vector<HypothesisEvent> history_;
  CellClassifier classify_;              // the predictor's cell states
  PredictionCoverage coverage_;          // unknown and undecided cells of hypotheses not refuted, best frame
  std::optional<Eigen::Vector2i> target_;
  std::optional<Eigen::Vector2i> predicted_target_;  // target of the last prediction requested
  Eigen::Vector2d target_set_at_ = Eigen::Vector2d::Zero();
  PSlamStats stats_;
  double last_time_ = 0.0;
  Pose2D move_since_request_;            // loop corrections since the running prediction was asked
};

const char* StatusName(Hypothesis::Status status);

}  // namespace pslam
