#pragma once
// Online odometry calibration: learns how far and how much the robot really moves per metre and
// per radian its wheel odometry reports, from stretches where scan matching pins the pose down,
// and scales the odometry with it everywhere else.
//
// Why: where the scan barely constrains a direction (a corridor longer than the laser's range),
// the degeneracy guard hands that direction to odometry, and a wheel-radius error of 1 % puts
// 0.2 m into every 20 m of such corridor. Scan-to-map matching measures that error well wherever
// the scan constrains both directions, so it can be taken out (cf. Kümmerle et al., "Simultaneous
// calibration, localization, and mapping", IROS 2011, who estimate the same scale factors).
//
// Estimate: the matched distance along the odometry's direction of travel summed over pairs of
// consecutive well-constrained scans, divided by the odometry's distance over the same pairs (the
// same for rotation). A ratio of sums, not a per-scan least squares: the matched poses' errors
// cancel within a stretch (the sum telescopes), so the estimate's noise does not grow with the
// number of scans. Old evidence fades over a window of travel, as a floor or a load may change.
#include "pslam/common/pose2d.hpp"

namespace pslam {

struct OdometryCalibrationOptions {
  // Off by default: on the logs it changes little either way (docs/loop-closure.md); the
  // simulated explorations turn it on.
  bool enabled = false;
  // A scan match counts as well constrained when the weaker translation direction of J^T J holds
  // at least this share of the stronger one (twice the degeneracy guard's default share).
  double min_constrained_ratio = 0.3;
  double window_metres = 50.0;      // evidence fades by e per this much odometry travel
  double window_radians = 30.0;     // ... and per this much odometry rotation
  double min_evidence_metres = 3.0; // the translation scale is used once this much travel backs it
  double min_evidence_radians = 3.0;
  double max_scale_error = 0.1;     // estimates are kept within 1 +- this
};

class OdometryCalibration {
 public:
  explicit OdometryCalibration(const OdometryCalibrationOptions& options) : options_(options) {}

  // One scan: the raw odometry pose, the pose scan matching put it at, and whether that match
  // constrained every direction. Pairs of consecutive constrained scans feed the estimate.
  void AddScan(const Pose2D& odometry, const Pose2D& matched, bool constrained);
  // The map frame moved under the matched poses (a loop closure): the next pair is not comparable.
  void Interrupt() { has_previous_ = false; }

  // An odometry increment (robot frame) scaled by the current estimates.
  Pose2D Correct(const Pose2D& odometry_delta) const;

  double translation_scale() const;  // true distance per odometry distance (1 until known)
  double rotation_scale() const;     // true rotation per odometry rotation (1 until known)

 private:
  // matched / odometry within the bounds, or 1 while off or short of evidence.
  double Scale(double matched, double odometry, double min_evidence) const;

  OdometryCalibrationOptions options_;
  bool has_previous_ = false;
  bool previous_constrained_ = false;
  Pose2D previous_odometry_, previous_matched_;
  double odometry_metres_ = 0.0, matched_metres_ = 0.0;    // faded sums over constrained pairs
  double odometry_radians_ = 0.0, matched_radians_ = 0.0;
};

}  // namespace pslam
