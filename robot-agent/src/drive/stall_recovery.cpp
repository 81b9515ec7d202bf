#include "drive/stall_recovery.hpp"

namespace pslam::agent {

VelocityCommand StallRecovery::Filter(const VelocityCommand& allowed, const Pose2D& odometry, double now) {
  if (backing_off(now)) return {-options_.back_off_speed, 0.0};
  if (allowed.v < options_.min_speed) {
    watching_ = false;  // standing or turning in place: nothing to stall
    return allowed;
  }
  if (!watching_ || (odometry.translation() - watch_pose_.translation()).norm() >= options_.min_progress_m) {
    watching_ = true;
    watch_pose_ = odometry;
    watch_since_ = now;
    return allowed;
  }
  if (now - watch_since_ < options_.stall_s) return allowed;
  ++stalls_;
  watching_ = false;
  back_off_until_ = now + options_.back_off_s;
  careful_until_ = back_off_until_ + options_.careful_s;
  return {-options_.back_off_speed, 0.0};
}

void StallRecovery::Reset() {
  watching_ = false;
  back_off_until_ = -1.0;
}

}  // namespace pslam::agent
