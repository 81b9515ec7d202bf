#pragma once
// The agent's time base: seconds since the Unix epoch (what the wire protocol's `t` means), but
// advancing with the monotonic clock so that an NTP step while the robot drives cannot make scan
// and odometry stamps jump relative to each other.
#include <chrono>

namespace pslam::agent {

class AgentClock {
 public:
  // Seconds since the epoch, anchored once per process to the system clock.
  static double Now() {
    static const Anchor anchor;
    const std::chrono::duration<double> since = std::chrono::steady_clock::now() - anchor.steady;
    return anchor.epoch_seconds + since.count();
  }

 private:
  struct Anchor {
    std::chrono::steady_clock::time_point steady = std::chrono::steady_clock::now();
    double epoch_seconds =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  };
};

}  // namespace pslam::agent
