#pragma once
// Getting a robot unstuck. The safety layer watches the corridor the laser sees ahead; a robot
// turning on an arc can still touch what stands beside it, behind the laser's plane, where no
// beam reaches: a door jamb at its shoulder. Pressed against it, the wheels stall (the Pioneer's
// motors stall, the simulator refuses the motion) and every forward command after it stalls too,
// so the robot stands there for good. When forward motion was commanded, allowed by the safety
// layer, and the odometry did not move for stall_s, the robot backs straight off for back_off_s:
// what it touches lies ahead of its centre, or it could have driven on. For careful_s after
// that, the path is followed with a shorter lookahead, so it cuts the corner less.
#include <algorithm>

#include "drive/velocity_command.hpp"
#include "pslam/common/pose2d.hpp"

namespace pslam::agent {

struct StallOptions {
  double stall_s = 2.0;            // forward commanded this long without moving: stalled
  double min_progress_m = 0.02;    // less than this counts as not moving
  double min_speed = 0.02;         // m/s: slower commands are not watched
  double back_off_s = 1.5;
  double back_off_speed = 0.1;     // m/s
  double careful_s = 10.0;
  double careful_lookahead_m = 0.25;
};

class StallRecovery {
 public:
  explicit StallRecovery(StallOptions options = {}) : options_(options) {}

  // The command to send at 'now' for a robot at 'odometry' instead of 'allowed' (what the
  // controller wants, as the safety layer let it through).
  VelocityCommand Filter(const VelocityCommand& allowed, const Pose2D& odometry, double now);
  // Forgets the watch and ends a back-off (the robot was stopped for another reason).
  void Reset();

  bool backing_off(double now) const { return now < back_off_until_; }
  bool careful(double now) const { return now < careful_until_; }
  // The follower's lookahead at 'now': 'normal', or careful_lookahead_m if shorter while careful.
  double Lookahead(double normal, double now) const {
    return careful(now) ? std::min(normal, options_.careful_lookahead_m) : normal;
  }
  int stalls() const { return stalls_; }

 private:
  StallOptions options_;
  bool watching_ = false;
  Pose2D watch_pose_;
  double watch_since_ = 0.0;
  double back_off_until_ = -1.0;
  double careful_until_ = -1.0;
  int stalls_ = 0;
};

}  // namespace pslam::agent
