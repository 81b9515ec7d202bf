#include "pslam/io/odometry_reversal.hpp"

#include <algorithm>

namespace pslam {

Pose2D OdometryReversalRepair::Signed(const Pose2D& step, bool backing_up) {
  if (!backing_up || step.x <= 0.0) return step;
  return {-step.x, -step.y, step.theta};  // a backward arc mirrors the forward one through the start
}

void OdometryReversalRepair::Apply(OdometryReading& odom) {
  const Pose2D raw = odom.pose;
  const double velocity = odom.translational_velocity;
  if (raw_last_) {
    const Pose2D step = Between(*raw_last_, raw);
    const bool backing_up = std::min(velocity_last_, velocity) < 0.0 && std::max(velocity_last_, velocity) <= 0.0;
    const Pose2D repaired = Signed(step, backing_up);
    if (repaired.x != step.x) ++repaired_steps_;
    // Until the first repair the poses are passed through untouched, not recomposed.
    if (repaired_steps_ > 0) odom.pose = repaired_last_ * repaired;
  }
  raw_last_ = raw;
  repaired_last_ = odom.pose;
  velocity_last_ = velocity;
}

void OdometryReversalRepair::Apply(LaserScan& scan) const {
  if (!raw_last_) return;
  const Pose2D step = Between(*raw_last_, scan.odometry);
  const Pose2D repaired = Signed(step, velocity_last_ < 0.0);
  if (repaired_steps_ > 0 || repaired.x != step.x) scan.odometry = repaired_last_ * repaired;
}

}  // namespace pslam
