#include "pslam/filter/rbpf.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "pslam/common/random.hpp"
#include "pslam/filter/resampling.hpp"
#include "pslam/grid/grid_transform.hpp"
#include "pslam/grid/prior_map.hpp"
#include "pslam/grid/stale_prior.hpp"
#include "pslam/matching/scan_likelihood.hpp"
#include "pslam/matching/scan_matcher.hpp"

namespace pslam {

Rbpf::Rbpf(const RbpfOptions& options)
    : options_(options), inserter_(options.insert), pool_(options.threads), calibration_(options.odometry_calibration) {
  if (options_.prior_map && std::abs(options_.prior_map->resolution() - options_.resolution) > 1e-9) {
    throw std::invalid_argument("the prior map's resolution differs from the filter's");
  }
  if (options_.loop_closure.enabled) {
    loop_closer_ = std::make_unique<LoopCloser>(options_.loop_closure, options_.insert, options_.resolution, &pool_);
  }
}

std::vector<double> Rbpf::Weights() const {
  std::vector<double> lw;
  lw.reserve(particles_.size());
  for (const auto& p : particles_) lw.push_back(p.log_weight);
  return NormalizeLogWeights(lw);
}

void Rbpf::SelectBest() {
  best_ = static_cast<int>(std::max_element(particles_.begin(), particles_.end(),
                                            [](const Particle& a, const Particle& b) { return a.log_weight < b.log_weight; }) -
                           particles_.begin());
}

void Rbpf::Resample(const std::vector<double>& weights) {
  auto rng = MakeStream(options_.seed, static_cast<std::uint64_t>(stats_.updates), ~0ull);
  const std::vector<int> picks = SystematicResample(weights, rng);
  SelectBest();
  const int previous_best = best_;
  std::vector<Particle> next;
  next.reserve(particles_.size());
  best_ = -1;
  for (int i : picks) {
    // All weights restart equal: keep following a copy of the particle that was best.
    if (i == previous_best && best_ < 0) best_ = static_cast<int>(next.size());
    next.push_back(particles_[static_cast<std::size_t>(i)]);
    next.back().log_weight = 0.0;
  }
  if (best_ < 0) best_ = 0;
  particles_ = std::move(next);
}

void Rbpf::InsertScan(const ScanPoints& points, const Pose2D& pose, OccupancyGrid& map,
                      OccupancyGrid* hypothesis) const {
  inserter_.Insert(points, pose, map, hypothesis);
  if (start_map_) ForgetPriorFloorBehindNewSurfaces(points, pose, *start_map_, options_.prior_forget_depth, map);
}

void Rbpf::Initialize(const LaserScan& scan) {
  const ScanPoints points = ToScanPoints(scan, options_.points);
  Particle first{options_.initial_pose, 0.0, OccupancyGrid(options_.resolution, options_.grid),
                 OccupancyGrid(options_.resolution, options_.grid),
                 std::make_shared<TrajectoryNode>(TrajectoryNode{options_.initial_pose, 0, nullptr}), {}};
  if (options_.prior_map) {
    // Copies share the prior's tiles: a particle pays only for the tiles it changes.
    first.map = CapPriorConfidence(*options_.prior_map, options_.prior_max_probability);
    start_map_ = std::make_shared<const OccupancyGrid>(first.map);
    // The given pose (a localizer's estimate) is a few centimetres off; every particle would start
    // there and map its first scans there, so the first scan is matched to the prior first.
    first.pose = MatchScan(first.map, points.hits, first.pose, options_.tracking_match).pose;
    first.node = std::make_shared<TrajectoryNode>(TrajectoryNode{first.pose, 0, nullptr});
    if (loop_closer_) loop_closer_->SetBaseMap(start_map_, options_.prior_forget_depth);
  }
  InsertScan(points, first.pose, first.map, nullptr);
  particles_.assign(static_cast<std::size_t>(std::max(1, options_.particles)), first);
  odometry_at_update_ = scan.odometry;
  tracked_.push_back(Pose2D());
  last_pose_ = first.pose;
  best_ = 0;
  if (loop_closer_) loop_closer_->AddNode(0, first.pose, points);
}

RbpfStep Rbpf::AddScan(const LaserScan& scan) {
  RbpfStep step;
  ++stats_.scans;
  if (particles_.empty()) {
    Initialize(scan);
    step.updated = true;
    step.neff = static_cast<double>(particles_.size());
    step.pose = last_pose_;
    ++stats_.updates;
    stats_.neff = step.neff;
    return step;
  }
  const ScanPoints points = ToScanPoints(scan, options_.points);
  // Track the scan against the best map, starting from where odometry says the robot went.
  const Particle& tracker = best();
  const Pose2D guess = tracker.pose * calibration_.Correct(Between(odometry_at_update_, scan.odometry));
  const ScanMatchResult tracked = MatchScan(tracker.map, points.hits, guess, options_.tracking_match);
  if (options_.odometry_calibration.enabled) {
    calibration_.AddScan(scan.odometry, tracked.pose,
                         tracked.converged && TranslationConstraintRatio(tracked.hessian) >=
                                                  options_.odometry_calibration.min_constrained_ratio);
  }
  step.tracking_score = tracked.score;
  const Pose2D motion = Between(tracker.pose, tracked.pose);
  tracked_.push_back(motion);
  last_pose_ = tracked.pose;

  const bool moved_enough = std::hypot(motion.x, motion.y) >= options_.linear_update ||
                            std::abs(motion.theta) >= options_.angular_update;
  if (moved_enough) {
    step.prediction = UpdateParticles(motion, points.hits);
    const std::vector<double> weights = Weights();
    step.neff = EffectiveSampleSize(weights);
    if (step.neff < options_.resample_threshold * static_cast<double>(particles_.size())) {
      Resample(weights);
      step.resampled = true;
      ++stats_.resamplings;
    } else {
      SelectBest();
    }
    pool_.ParallelFor(static_cast<int>(particles_.size()), [&](int i) {
      Particle& p = particles_[static_cast<std::size_t>(i)];
      InsertScan(points, p.pose, p.map, has_hypotheses_ ? &p.hypothesis : nullptr);
    });
    odometry_at_update_ = scan.odometry;
    if (loop_closer_) {
      const int scan_index = static_cast<int>(tracked_.size()) - 1;
      if (auto correction = loop_closer_->AddNode(scan_index, best().pose, points)) {
        step.correction = ApplyCorrection(*correction);
        step.loop_corrected = true;
      }
    }
    last_pose_ = best().pose;
    step.updated = true;
    ++stats_.updates;
    stats_.neff = step.neff;
  } else {
    step.neff = stats_.neff;
  }
  step.best = best_;
  step.pose = last_pose_;
  return step;
}

std::optional<Pose2D> Rbpf::FlushLoopClosure() {
  if (!loop_closer_ || particles_.empty()) return std::nullopt;
  auto correction = loop_closer_->Flush();
  if (!correction) return std::nullopt;
  const Pose2D move = ApplyCorrection(*correction);
  last_pose_ = best().pose;
  return move;
}

Pose2D Rbpf::ApplyCorrection(const LoopClosureCorrection& correction) {
  calibration_.Interrupt();
  const Pose2D old_best = best().pose;
  const Pose2D new_best = correction.node_poses.back();
  const Pose2D move = new_best * old_best.inverse();
  // The corrected history, shared by every particle up to the previous update.
  std::shared_ptr<const TrajectoryNode> history;
  for (std::size_t k = 0; k + 1 < correction.node_poses.size(); ++k) {
    history = std::make_shared<TrajectoryNode>(TrajectoryNode{correction.node_poses[k], correction.node_scans[k], history});
  }
  const int scan_index = correction.node_scans.back();
  for (Particle& p : particles_) {  // copying a grid touches the source's write cache: not in parallel
    // Particles keep their spread around the best one; all share the re-rendered map.
    p.pose = new_best * Between(old_best, p.pose);
    p.map = correction.map;
    p.node = std::make_shared<TrajectoryNode>(TrajectoryNode{p.pose, scan_index, history});
    // Callers move their hypothesis cells by `move` too (RemoveHypothesis takes them so).
    for (Pose2D& frame : p.hypothesis_frames) frame = move * frame * move.inverse();
  }
  if (has_hypotheses_) {
    pool_.ParallelFor(static_cast<int>(particles_.size()), [&](int i) {
      Particle& p = particles_[static_cast<std::size_t>(i)];
      p.hypothesis = TransformGrid(p.hypothesis, move);
    });
  }
  return move;
}

PredictionUse Rbpf::UpdateParticles(const Pose2D& motion, const std::vector<Eigen::Vector2f>& hits) {
  const int scan_index = static_cast<int>(tracked_.size()) - 1;
  const auto update = static_cast<std::uint64_t>(stats_.updates);
  const bool with_hypotheses = has_hypotheses_ && options_.use_predictions;
  std::vector<ScanLikelihood> likelihoods(particles_.size());
  pool_.ParallelFor(static_cast<int>(particles_.size()), [&](int i) {
    Particle& p = particles_[static_cast<std::size_t>(i)];
    auto rng = MakeStream(options_.seed, update, static_cast<std::uint64_t>(i));
    p.pose = p.pose * SampleMotion(motion, options_.motion, rng);
    const ScanMatchResult match = MatchScan(p.map, hits, p.pose, options_.particle_match);
    if (match.converged) p.pose = match.pose;
    likelihoods[static_cast<std::size_t>(i)] =
        ComputeScanLikelihood(p.map, hits, p.pose, options_.likelihood, with_hypotheses ? &p.hypothesis : nullptr);
    p.node = std::make_shared<TrajectoryNode>(TrajectoryNode{p.pose, scan_index, p.node});
  });

  // Recovery (section IV-C): the hypotheses weigh in only where some particle's hit ratio shows
  // that they agree with what the robot sees.
  PredictionUse use;
  int with_points = 0;
  for (const ScanLikelihood& l : likelihoods) {
    if (l.hypothesis_points < options_.min_hypothesis_points) continue;
    ++with_points;
    use.best_hit_ratio = std::max(use.best_hit_ratio, l.hit_ratio());
    use.mean_hit_ratio += l.hit_ratio();
  }
  if (with_points > 0) {
    use.measured = true;
    use.mean_hit_ratio /= with_points;
    use.used = !options_.recovery || use.best_hit_ratio >= options_.hit_ratio_threshold;
    ++stats_.updates_with_hypothesis_points;
    if (use.used) ++stats_.updates_using_predictions;
  }
  use.hypothesis_points = likelihoods[static_cast<std::size_t>(best_)].hypothesis_points;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    particles_[i].log_weight += likelihoods[i].Total(use.used) / options_.likelihood_temperature;
  }
  return use;
}

void Rbpf::ForEachCellInParticles(
    int index, const std::vector<PredictedCell>& cells,
    const std::function<void(Particle&, const Eigen::Vector2i&, const PredictedCell&)>& visit) {
  if (cells.empty() || particles_.empty() || index < 0) return;
  pool_.ParallelFor(static_cast<int>(particles_.size()), [&](int i) {
    Particle& p = particles_[static_cast<std::size_t>(i)];
    const Pose2D& to_particle = p.hypothesis_frames[static_cast<std::size_t>(index)];
    for (const PredictedCell& c : cells) visit(p, p.map.WorldToCell(to_particle * p.map.CellCenter(c.cell)), c);
  });
}

int Rbpf::AddHypothesis(const std::vector<PredictedCell>& cells) {
  if (particles_.empty()) return -1;  // nothing to predict for before the first scan
  const int index = static_cast<int>(best().hypothesis_frames.size());
  const Pose2D best_inverse = best().pose.inverse();
  for (Particle& p : particles_) p.hypothesis_frames.push_back(p.pose * best_inverse);
  if (cells.empty()) return index;
  constexpr int kOccupied = 3000, kFree = -2000;  // milli log-odds: p = 0.95 and 0.12
  ForEachCellInParticles(index, cells, [](Particle& p, const Eigen::Vector2i& cell, const PredictedCell& c) {
    if (p.map.IsKnown(cell.x(), cell.y())) return;
    p.hypothesis.MutableAt(cell.x(), cell.y()) = static_cast<OccupancyGrid::Cell>(c.occupied ? kOccupied : kFree);
  });
  has_hypotheses_ = true;
  return index;
}

void Rbpf::RemoveHypothesis(int index, const std::vector<PredictedCell>& cells) {
  ForEachCellInParticles(index, cells, [](Particle& p, const Eigen::Vector2i& cell, const PredictedCell&) {
    p.hypothesis.Forget(cell.x(), cell.y());
  });
}

std::vector<int> Rbpf::UpdateScanIndices() const {
  std::vector<int> out;
  if (particles_.empty()) return out;
  for (const TrajectoryNode* n = best().node.get(); n; n = n->parent.get()) out.push_back(n->scan_index);
  std::reverse(out.begin(), out.end());
  return out;
}

std::vector<Pose2D> Rbpf::Trajectory() const {
  std::vector<Pose2D> out(tracked_.size());
  if (particles_.empty()) return out;
  std::vector<const TrajectoryNode*> chain;
  for (const TrajectoryNode* n = best().node.get(); n; n = n->parent.get()) chain.push_back(n);
  std::reverse(chain.begin(), chain.end());
  for (std::size_t k = 0; k < chain.size(); ++k) {
    const TrajectoryNode& a = *chain[k];
    const int begin = a.scan_index;
    const int end = k + 1 < chain.size() ? chain[k + 1]->scan_index : static_cast<int>(tracked_.size());
    out[static_cast<std::size_t>(begin)] = a.pose;
    // Spread the disagreement between tracking and the next update evenly over the scans between.
    Pose2D correction;
    if (k + 1 < chain.size()) correction = Between(a.pose * tracked_[static_cast<std::size_t>(end)], chain[k + 1]->pose);
    for (int s = begin + 1; s < end; ++s) {
      const double t = static_cast<double>(s - begin) / static_cast<double>(end - begin);
      out[static_cast<std::size_t>(s)] = a.pose * tracked_[static_cast<std::size_t>(s)] * Interpolate(Pose2D(), correction, t);
    }
  }
  return out;
}

double Rbpf::MapBytes() const {
  double bytes = 0.0;
  for (const Particle& p : particles_) bytes += p.map.SharedBytes() + p.hypothesis.SharedBytes();
  return bytes;
}

std::uint64_t Rbpf::RefusedMapWrites() const {
  std::uint64_t refused = 0;
  for (const Particle& p : particles_) refused = std::max({refused, p.map.refused_writes(), p.hypothesis.refused_writes()});
  return refused;
}

}  // namespace pslam
