#include "pslam/slam/pslam.hpp"

#include <chrono>
#include <cmath>
#include <thread>
#include <utility>

#include "pslam/slam/heading_target.hpp"
#include "pslam/slam/hypothesis_judge.hpp"
#include "pslam/slam/local_refutation.hpp"
#include "pslam/slam/sealed_predictions.hpp"

namespace pslam {
namespace {

constexpr OccupancyGrid::Cell kPredictedOccupied = 3000;  // milli log-odds, p = 0.95
constexpr OccupancyGrid::Cell kPredictedFree = -2000;     // p = 0.12

std::vector<PredictedCell> ToPredictedCells(const std::vector<HypothesisCell>& from) {
  std::vector<PredictedCell> cells;
  cells.reserve(from.size());
  for (const HypothesisCell& c : from) cells.push_back({c.cell, c.occupied});
  return cells;
}

std::vector<PredictedCell> ToPredictedCells(const Hypothesis& h) { return ToPredictedCells(h.cells); }

// Hypotheses that weigh the particles (S2 of eq. 22).
bool Weighing(Hypothesis::Status s) { return s == Hypothesis::Status::kPending || s == Hypothesis::Status::kConfirmed; }
// Hypotheses that stand for unexplored space: all but the refuted.
bool Covering(Hypothesis::Status s) { return s != Hypothesis::Status::kRefuted; }

}  // namespace

const char* StatusName(Hypothesis::Status status) {
  switch (status) {
    case Hypothesis::Status::kPending: return "pending";
    case Hypothesis::Status::kConfirmed: return "confirmed";
    case Hypothesis::Status::kRefuted: return "refuted";
    case Hypothesis::Status::kExpired: return "expired";
  }
  return "unknown";
}

PSlam::PSlam(const PSlamOptions& options)
    : options_(options),
      filter_(options.filter),
      classify_(options.predictor.states),
      coverage_(options.filter.resolution) {
  if (!options_.predict) options_.filter.use_predictions = false;
  if (options_.predict) predictor_ = std::make_unique<AsyncPredictor>(options_.predictor, options_.library);
}

PSlamStats PSlam::stats() const {
  PSlamStats s = stats_;
  if (predictor_) {
    const AsyncPredictorStats a = predictor_->stats();
    s.predictions_requested = static_cast<int>(a.accepted);
    s.predictions_made = static_cast<int>(a.completed);
    s.last_prediction_ms = a.last_ms;
    s.max_prediction_ms = a.max_ms;
    s.outcomes = a.outcomes;
  }
  return s;
}

void PSlam::SetTarget(const Eigen::Vector2i& cell, double time) {
  if (target_ && *target_ == cell) return;
  target_ = cell;
  target_set_at_ = filter_.particles().empty() ? Eigen::Vector2d::Zero() : filter_.best().pose.translation();
  ++stats_.targets;
  const double resolution = options_.filter.resolution;
  if (predicted_target_ &&
      (*predicted_target_ - cell).cast<double>().norm() * resolution < options_.new_target_distance_m) {
    return;  // the same exploration goal, replanned
  }
  if (!predictor_ || filter_.particles().empty()) return;
  // H of eq. 20 works on the best particle's map (copying it copies tile pointers only). A request
  // the busy predictor drops leaves predicted_target_ alone, so the next target asks again.
  OccupancyGrid input = options_.predict_on_merged_map ? MergedMap(options_.predict_from_psi) : filter_.best().map;
  if (predictor_->Request(std::move(input), cell, time)) {
    move_since_request_ = Pose2D();
    predicted_target_ = cell;
    ++stats_.new_targets;
  }
}

PSlamStep PSlam::AddScan(const LaserScan& scan) {
  PSlamStep step;
  last_time_ = scan.timestamp;
  step.filter = filter_.AddScan(scan);
  if (step.filter.loop_corrected) FollowCorrection(step.filter.correction, &step.changed_hypotheses);
  if (!predictor_) return step;
  TakePrediction(scan.timestamp);
  if (step.filter.updated) {
    JudgeHypotheses(step.filter, scan.timestamp, step.changed_hypotheses);
    if (options_.heading_targets) MaybeRetargetFromHeading(scan.timestamp);
  }
  return step;
}

void PSlam::FollowCorrection(const Pose2D& move, std::vector<int>* changed) {
  const double resolution = options_.filter.resolution;
  const OccupancyGrid lattice(resolution);
  const auto cell = [&](const Eigen::Vector2i& c) { return lattice.WorldToCell(move * lattice.CellCenter(c)); };
  coverage_ = PredictionCoverage(resolution);
  for (std::size_t i = 0; i < hypotheses_.size(); ++i) {
    MoveHypothesis(hypotheses_[i], move, resolution);
    MoveHypothesis(originals_[i], move, resolution);
    if (changed) changed->push_back(hypotheses_[i].id);
    if (!Covering(hypotheses_[i].status)) continue;
    coverage_.Add(hypotheses_[i].cells);
    coverage_.Add(hypotheses_[i].undecided_cells);
  }
  if (target_) target_ = cell(*target_);
  if (predicted_target_) predicted_target_ = cell(*predicted_target_);
  target_set_at_ = move * target_set_at_;
  move_since_request_ = move * move_since_request_;
}

bool PSlam::FlushLoopClosure() {
  const std::optional<Pose2D> move = filter_.FlushLoopClosure();
  if (move) FollowCorrection(*move, nullptr);
  return move.has_value();
}

void PSlam::MaybeRetargetFromHeading(double time) {
  const Pose2D& pose = filter_.best().pose;
  const bool reached = target_ && filter_.best().map.IsKnown(target_->x(), target_->y()) &&
                       (filter_.best().map.CellCenter(*target_) - pose.translation()).norm() < 1.0;
  const bool far = (pose.translation() - target_set_at_).norm() > options_.heading.retarget_distance;
  if (target_ && !reached && !far) return;
  if (const auto cell = HeadingFrontierTarget(filter_.best().map, pose, options_.heading)) SetTarget(*cell, time);
  else target_set_at_ = pose.translation();  // nothing ahead: look again after driving on
}

void PSlam::TakePrediction(double time) {
  std::optional<Hypothesis> h = predictor_->TakeResult();
  if (!h || h->cells.empty()) return;
  // The map may have been corrected, and has moved on, while the predictor worked.
  if (move_since_request_.x != 0.0 || move_since_request_.y != 0.0 || move_since_request_.theta != 0.0) {
    MoveHypothesis(*h, move_since_request_, options_.filter.resolution);
  }
  TakeExplored(*h, filter_.best().map);
  if (options_.judge.drop_sealed_off) TakeSealedOff(*h, filter_.best().map, classify_);
  if (h->cells.empty()) return;
  filter_index_.push_back(filter_.AddHypothesis(ToPredictedCells(*h)));
  coverage_.Add(h->cells);
  coverage_.Add(h->undecided_cells);
  ++stats_.hypotheses;
  originals_.push_back(*h);
  hypotheses_.push_back(std::move(*h));
  last_observed_.push_back(time);
  history_.push_back({hypotheses_.back().id, time, Hypothesis::Status::kPending});
}

void PSlam::SetStatus(std::size_t i, Hypothesis::Status status, double time) {
  Hypothesis& h = hypotheses_[i];
  if (h.status == status) return;
  const Hypothesis::Status before = h.status;
  h.status = status;
  history_.push_back({h.id, time, status});
  if (status == Hypothesis::Status::kConfirmed) ++stats_.confirmed;
  if (status == Hypothesis::Status::kRefuted) ++stats_.refuted;
  if (status == Hypothesis::Status::kExpired) ++stats_.expired;
  // A refuted or expired prediction must not weigh the particles any more.
  if (Weighing(before) && !Weighing(status)) filter_.RemoveHypothesis(filter_index_[i], ToPredictedCells(h));
  if (Covering(before) && !Covering(status)) {
    coverage_.Remove(h.cells);
    coverage_.Remove(h.undecided_cells);
  }
}

void PSlam::JudgeHypotheses(const RbpfStep& step, double time, std::vector<int>& changed) {
  const OccupancyGrid& map = filter_.best().map;
  for (std::size_t i = 0; i < hypotheses_.size(); ++i) {
    Hypothesis& h = hypotheses_[i];
    if (!Covering(h.status)) continue;
    const std::vector<HypothesisCell> seen = TakeExplored(h, map);
    coverage_.Remove(seen);
    coverage_.Remove(TakeDecided(h, map, classify_));
    WithdrawAroundContradictions(i, seen);
    // Confirmed hypotheses are settled; expired ones are judged again if the robot comes back,
    // so that only an observation that contradicts them withdraws their coverage.
    if (h.status == Hypothesis::Status::kConfirmed) continue;
    if (seen.empty()) {
      if (h.status == Hypothesis::Status::kPending && time - last_observed_[i] > options_.judge.expiry_s) {
        SetStatus(i, Hypothesis::Status::kExpired, time);
        changed.push_back(h.id);
      }
      continue;
    }
    last_observed_[i] = time;
    // Hit ratio (eq. 23) as the filter measured it while this hypothesis was in view; an update
    // with too few endpoints in hypotheses measured nothing, and its zero must not count.
    if (step.prediction.measured) {
      h.hit_ratio = std::isnan(h.hit_ratio) ? step.prediction.best_hit_ratio
                                            : 0.7 * h.hit_ratio + 0.3 * step.prediction.best_hit_ratio;
    }
    const ObservedEvidence evidence =
        GatherEvidence(originals_[i], map, options_.predictor.states, options_.predictor.tolerance_cells);
    h.psi_observed = evidence.psi;
    const Verdict verdict = JudgeOnMap(originals_[i], evidence, map, options_.predictor.states,
                                       options_.predictor.tolerance_cells, options_.judge);
    if (verdict == Verdict::kRefuted) SetStatus(i, Hypothesis::Status::kRefuted, time);
    // An expired hypothesis that turns out right stays out of the weights: it is settled.
    if (verdict == Verdict::kConfirmed && h.status == Hypothesis::Status::kPending) {
      SetStatus(i, Hypothesis::Status::kConfirmed, time);
    }
    changed.push_back(h.id);
  }
}

void PSlam::WithdrawAroundContradictions(std::size_t i, const std::vector<HypothesisCell>& seen) {
  const double resolution = options_.filter.resolution;
  const double radius = options_.judge.local_refutation_radius_m / resolution;
  if (seen.empty() || radius <= 0.0) return;
  const int tolerance = std::max(options_.predictor.tolerance_cells,
                                 static_cast<int>(std::lround(options_.judge.registration_m / resolution)));
  Hypothesis& h = hypotheses_[i];
  std::vector<HypothesisCell> withdrawn =
      TakeNear(h, FindContradictions(seen, originals_[i], filter_.best().map, classify_, tolerance), radius);
  if (withdrawn.empty()) return;
  // What the withdrawn cells joined to the robot's floor may now be cut off from it.
  if (options_.judge.drop_sealed_off) {
    const std::vector<HypothesisCell> sealed = TakeSealedOff(h, filter_.best().map, classify_);
    withdrawn.insert(withdrawn.end(), sealed.begin(), sealed.end());
  }
  coverage_.Remove(withdrawn);
  if (Weighing(h.status)) filter_.RemoveHypothesis(filter_index_[i], ToPredictedCells(withdrawn));
}

PredictionCoverage PSlam::SettledCoverage() const {
  PredictionCoverage settled(options_.filter.resolution);
  for (const Hypothesis& h : hypotheses_) {
    if (h.status != Hypothesis::Status::kConfirmed && h.status != Hypothesis::Status::kExpired) continue;
    settled.Add(h.cells);
    settled.Add(h.undecided_cells);
  }
  return settled;
}

bool PSlam::IsCovered(const Eigen::Vector2i& cell) const { return coverage_.Covered(cell); }

bool PSlam::IsPredictedWall(const Eigen::Vector2i& cell) const { return coverage_.PredictedWall(cell); }

OccupancyGrid PSlam::MergedMap(double min_psi) const {
  OccupancyGrid merged = filter_.best().map;
  const auto write = [&merged](const HypothesisCell& c) {
    merged.MutableAt(c.cell.x(), c.cell.y()) = c.occupied ? kPredictedOccupied : kPredictedFree;
  };
  for (const Hypothesis& h : hypotheses_) {
    if (!Covering(h.status)) continue;
    if (h.psi < min_psi && h.status != Hypothesis::Status::kConfirmed) continue;
    for (const HypothesisCell& c : h.cells) {
      if (!merged.IsKnown(c.cell.x(), c.cell.y())) write(c);
    }
    for (const HypothesisCell& c : h.undecided_cells) {
      if (classify_(merged.At(c.cell.x(), c.cell.y())) == CellState::kUncertain) write(c);
    }
  }
  return merged;
}

void PSlam::ScoreHypotheses() {
  const OccupancyGrid& map = filter_.best().map;
  for (std::size_t i = 0; i < hypotheses_.size(); ++i) {
    hypotheses_[i].psi_observed =
        ObservedSimilarity(originals_[i], map, options_.predictor.states, options_.predictor.tolerance_cells);
  }
}

void PSlam::FlushPredictions() {
  if (!predictor_) return;
  while (predictor_->busy()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  TakePrediction(last_time_);
}

}  // namespace pslam
