#include "pslam/matching/scan_matcher.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>

#include "pslam/matching/occupancy_field.hpp"

namespace pslam {
namespace {

struct Linearization {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  double cost = 0.0;  // sum of (1 - M)^2
  Eigen::Matrix3d scan_hessian = Eigen::Matrix3d::Zero();  // H without the prior: what the scan constrains
};

Linearization Linearize(const OccupancyField& field, const std::vector<Eigen::Vector2f>& points, const Pose2D& pose,
                        bool with_jacobian) {
  Linearization lin;
  const float c = static_cast<float>(std::cos(pose.theta)), s = static_cast<float>(std::sin(pose.theta));
  const Eigen::Vector2f t(static_cast<float>(pose.x), static_cast<float>(pose.y));
  for (const auto& p : points) {
    const Eigen::Vector2f w(c * p.x() - s * p.y() + t.x(), s * p.x() + c * p.y() + t.y());
    Eigen::Vector2f grad;
    const float m = field.Value(w, with_jacobian ? &grad : nullptr);
    const double r = 1.0 - m;
    lin.cost += r * r;
    if (!with_jacobian) continue;
    // d(world)/d(theta) = (-s px - c py, c px - s py)
    const float dth = grad.x() * (-s * p.x() - c * p.y()) + grad.y() * (c * p.x() - s * p.y());
    const Eigen::Vector3d J(grad.x(), grad.y(), dth);
    // J J^T is symmetric: sum its upper triangle and mirror it once at the end.
    lin.H(0, 0) += J(0) * J(0), lin.H(0, 1) += J(0) * J(1), lin.H(0, 2) += J(0) * J(2);
    lin.H(1, 1) += J(1) * J(1), lin.H(1, 2) += J(1) * J(2), lin.H(2, 2) += J(2) * J(2);
    lin.g.noalias() += J * r;
  }
  lin.H(1, 0) = lin.H(0, 1), lin.H(2, 0) = lin.H(0, 2), lin.H(2, 1) = lin.H(1, 2);
  lin.scan_hessian = lin.H;
  return lin;
}

Pose2D ApplyStep(const Pose2D& pose, const Eigen::Vector3d& delta, const ScanMatchOptions& o) {
  const double tn = delta.head<2>().norm();
  const double scale = tn > o.max_translation_step ? o.max_translation_step / tn : 1.0;
  return {pose.x + delta.x() * scale, pose.y + delta.y() * scale,
          pose.theta + std::clamp(delta.z(), -o.max_rotation_step, o.max_rotation_step)};
}

// Solution remapping: drops the part of the translation step along a direction the scan barely
// constrains (see ScanMatchOptions::degenerate_ratio).
void RemoveDegenerateTranslation(const Eigen::Matrix3d& H, double ratio, Eigen::Vector3d& delta) {
  if (ratio <= 0.0) return;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(H.topLeftCorner<2, 2>());
  const Eigen::Vector2d values = eigen.eigenvalues();  // ascending
  if (values(0) >= ratio * values(1)) return;
  const Eigen::Vector2d weak = eigen.eigenvectors().col(0);
  delta.head<2>() -= weak * weak.dot(delta.head<2>());
}

// Adds the prior toward 'guess' (ScanMatchOptions::prior_*_weight) to a linearization at 'pose';
// its scan_hessian, which the degeneracy guard reads, stays the scan's own.
void AddPrior(const Pose2D& pose, const Pose2D& guess, double points, const ScanMatchOptions& o, Linearization& lin) {
  const Eigen::Vector3d w2 = points * Eigen::Vector3d(o.prior_translation_weight * o.prior_translation_weight,
                                                      o.prior_translation_weight * o.prior_translation_weight,
                                                      o.prior_rotation_weight * o.prior_rotation_weight);
  const Eigen::Vector3d e(pose.x - guess.x, pose.y - guess.y, NormalizeAngle(pose.theta - guess.theta));
  lin.H.diagonal() += w2;
  lin.g -= w2.cwiseProduct(e);
  lin.cost += w2.dot(e.cwiseProduct(e));
}

// Levenberg-Marquardt on one level: a step is kept only if it lowers the cost, otherwise the
// damping grows. Bilinear occupancy is not smooth, and plain Gauss-Newton overshoots on it.
void RefineOnLevel(const OccupancyField& field, const std::vector<Eigen::Vector2f>& points, const Pose2D& guess,
                   Pose2D& pose, const ScanMatchOptions& o, Eigen::Matrix3d* hessian) {
  const bool with_prior = o.prior_translation_weight > 0.0 || o.prior_rotation_weight > 0.0;
  const double count = static_cast<double>(points.size());
  const auto linearize = [&](const Pose2D& at) {
    Linearization lin = Linearize(field, points, at, true);
    if (with_prior) AddPrior(at, guess, count, o, lin);
    return lin;
  };
  Linearization lin = linearize(pose);
  double lambda = o.damping;
  for (int it = 0; it < o.iterations_per_level; ++it) {
    if (lin.H.diagonal().minCoeff() <= 1e-9) break;  // no structure in view along some axis
    Eigen::Matrix3d A = lin.H;
    A.diagonal() *= 1.0 + lambda;
    Eigen::Vector3d delta = A.ldlt().solve(lin.g);
    if (!delta.allFinite()) break;
    RemoveDegenerateTranslation(lin.scan_hessian, o.degenerate_ratio, delta);
    const Pose2D candidate = ApplyStep(pose, delta, o);
    Linearization next = linearize(candidate);
    if (next.cost < lin.cost) {
      pose = candidate;
      lin = std::move(next);
      lambda = std::max(lambda / 4.0, 1e-6);
      if (delta.head<2>().norm() < 1e-4 && std::abs(delta.z()) < 1e-4) break;
    } else {
      lambda *= 8.0;
      if (lambda > 1e3) break;
    }
  }
  if (hessian) *hessian = lin.scan_hessian;
}

}  // namespace

double TranslationConstraintRatio(const Eigen::Matrix3d& hessian) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(hessian.topLeftCorner<2, 2>());
  const Eigen::Vector2d values = eigen.eigenvalues();  // ascending
  return values(1) > 0.0 ? std::max(0.0, values(0)) / values(1) : 0.0;
}

namespace {
// Mean evidence of the points at a pose.
double MeanEvidence(const OccupancyField& field, const std::vector<Eigen::Vector2f>& points, const Pose2D& pose) {
  if (points.empty()) return 0.0;
  const float c = static_cast<float>(std::cos(pose.theta)), s = static_cast<float>(std::sin(pose.theta));
  double sum = 0.0;
  for (const auto& p : points) {
    const Eigen::Vector2f w(c * p.x() - s * p.y() + static_cast<float>(pose.x), s * p.x() + c * p.y() + static_cast<float>(pose.y));
    sum += field.Value(w, nullptr);
  }
  return sum / static_cast<double>(points.size());
}
}  // namespace

double ScoreScan(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points, const Pose2D& pose) {
  return MeanEvidence(OccupancyField(grid, 0), points, pose);
}

namespace {

bool SamePose(const Pose2D& a, const Pose2D& b) {
  return std::hypot(a.x - b.x, a.y - b.y) < 1e-3 && std::abs(NormalizeAngle(a.theta - b.theta)) < 1e-3;
}

// Matches from coarsest_level down to 0 and keeps the pose it reached before the finest level in
// 'before_finest'. Given 'join', another match's pose there, it ends (nullopt) if it reached the
// same pose: the finest level would then take it where it took the other. (Compared on coarser
// levels too, a match that joined there still parted now and then: ACES seed 2 went from 0.0375 to
// 0.0383 m.)
std::optional<ScanMatchResult> MatchFromLevel(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points,
                                              const Pose2D& initial, const ScanMatchOptions& o, int coarsest_level,
                                              std::optional<Pose2D>* before_finest, const std::optional<Pose2D>& join) {
  ScanMatchResult result;
  result.pose = initial;
  for (int level = coarsest_level; level >= 0; --level) {
    if (level == 0) {
      if (before_finest) *before_finest = result.pose;
      if (join && SamePose(*join, result.pose)) return std::nullopt;
    }
    RefineOnLevel(OccupancyField(grid, level, o.hit_offsets), points, initial, result.pose, o,
                  level == 0 ? &result.hessian : nullptr);
  }
  result.score = MeanEvidence(OccupancyField(grid, 0, o.hit_offsets), points, result.pose);
  const Pose2D correction = Between(initial, result.pose);
  result.converged = result.score >= o.min_score && std::hypot(correction.x, correction.y) <= o.max_correction_translation &&
                     std::abs(correction.theta) <= o.max_correction_rotation;
  if (!result.converged) result.pose = initial;
  return result;
}

}  // namespace

ScanMatchResult MatchScan(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points,
                          const Pose2D& initial, const ScanMatchOptions& o) {
  if (points.empty()) return ScanMatchResult{.pose = initial};
  std::optional<Pose2D> first_before_finest;
  ScanMatchResult result = *MatchFromLevel(grid, points, initial, o, o.coarsest_level, &first_before_finest, std::nullopt);
  // Only a first match that found a hold on the map is second-guessed: where it found none, a
  // narrower start from the same guess is no more to be trusted, and the guess stands. Two
  // optima that score alike say the scan is ambiguous there: the first stands then too. Most second
  // matches reach the first one's pose before the finest level and end there.
  if (result.converged && o.second_start_level >= 0 && o.second_start_level != o.coarsest_level) {
    const std::optional<ScanMatchResult> second =
        MatchFromLevel(grid, points, initial, o, o.second_start_level, nullptr, first_before_finest);
    if (second && second->converged && second->score > o.second_start_margin * result.score) result = *second;
  }
  return result;
}

}  // namespace pslam
