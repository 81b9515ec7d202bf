#include "pslam/filter/odometry_calibration.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {
namespace {

// Below these an increment's direction is noise: it says nothing about a scale.
constexpr double kMinMetres = 0.005;
constexpr double kMinRadians = 0.01;

// A pair whose match disagrees with odometry by more than this is a matching slip or a bump, not
// a calibration error (10 % of a scan's travel is a few millimetres).
bool Plausible(double odometry, double matched) {
  return std::abs(matched - odometry) <= 0.02 + 0.2 * odometry;
}

}  // namespace

void OdometryCalibration::AddScan(const Pose2D& odometry, const Pose2D& matched, bool constrained) {
  if (has_previous_ && previous_constrained_ && constrained) {
    const Pose2D odometry_delta = Between(previous_odometry_, odometry);
    const Pose2D matched_delta = Between(previous_matched_, matched);
    const double metres = std::hypot(odometry_delta.x, odometry_delta.y);
    if (metres >= kMinMetres) {
      const double along = (matched_delta.x * odometry_delta.x + matched_delta.y * odometry_delta.y) / metres;
      if (Plausible(metres, along)) {
        const double fade = std::exp(-metres / options_.window_metres);
        odometry_metres_ = odometry_metres_ * fade + metres;
        matched_metres_ = matched_metres_ * fade + along;
      }
    }
    const double radians = std::abs(odometry_delta.theta);
    if (radians >= kMinRadians) {
      const double turned = std::copysign(1.0, odometry_delta.theta) * matched_delta.theta;
      if (Plausible(radians, turned)) {
        const double fade = std::exp(-radians / options_.window_radians);
        odometry_radians_ = odometry_radians_ * fade + radians;
        matched_radians_ = matched_radians_ * fade + turned;
      }
    }
  }
  has_previous_ = true;
  previous_constrained_ = constrained;
  previous_odometry_ = odometry;
  previous_matched_ = matched;
}

double OdometryCalibration::Scale(double matched, double odometry, double min_evidence) const {
  if (!options_.enabled || odometry < min_evidence) return 1.0;
  return std::clamp(matched / odometry, 1.0 - options_.max_scale_error, 1.0 + options_.max_scale_error);
}

double OdometryCalibration::translation_scale() const {
  return Scale(matched_metres_, odometry_metres_, options_.min_evidence_metres);
}

double OdometryCalibration::rotation_scale() const {
  return Scale(matched_radians_, odometry_radians_, options_.min_evidence_radians);
}

Pose2D OdometryCalibration::Correct(const Pose2D& d) const {
  const double k = translation_scale();
  return {d.x * k, d.y * k, d.theta * rotation_scale()};
}

}  // namespace pslam
