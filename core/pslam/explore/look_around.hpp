#pragma once
// A turn in place by a given angle, counted on the robot's heading as it changes (odometry on a
// robot, the truth in the simulator): how a robot looks all around it before a search for its
// place, since its laser sees only ahead.
#include <algorithm>
#include <cmath>
#include <numbers>

namespace pslam {

class LookAround {
 public:
  explicit LookAround(double rate = 0.5) : rate_(rate) {}  // rad/s: every scan overlaps the last

  // Turns 'radians' from 'heading' on; a turn under way is finished first (the longer one counts).
  void Start(double radians, double heading) {
    left_ = std::max(left_, radians);
    heading_ = heading;
  }
  // The angular velocity to command at 'heading': the rate until the turn is done, then 0.
  double Update(double heading) {
    if (left_ <= 0.0) return 0.0;
    left_ -= std::abs(std::remainder(heading - heading_, 2.0 * std::numbers::pi));
    heading_ = heading;
    return active() ? rate_ : 0.0;
  }
  bool active() const { return left_ > 0.0; }

 private:
  double rate_;
  double left_ = 0.0;     // rad still to turn
  double heading_ = 0.0;  // at the last Start or Update
};

}  // namespace pslam
