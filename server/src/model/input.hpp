#pragma once
// One raw input from an agent (or a replayed log) exactly as it is stored for replay: the filter is
// rebuilt from these alone, so they carry everything a LaserScan needs besides the session's laser.
#include <cstdint>
#include <string>
#include <vector>

namespace pslam::server {

enum class InputKind : int { kOdometry = 1, kScan = 2 };

struct InputRecord {
  std::int64_t seq = 0;           // per-session sequence number, from 1, odometry and scans share it
  InputKind kind = InputKind::kScan;
  double t = 0.0;                 // acquisition time, Unix seconds
  double x = 0.0, y = 0.0, theta = 0.0;  // raw odometry (for scans: interpolated to the scan time)
  double v = 0.0, w = 0.0;        // odometry only: translational and rotational velocity
  std::vector<float> ranges;      // scans only, metres; NaN marks a beam without a return
  std::string stamp;              // the source's timestamp text when it has one (CARMEN), for RPE
};

}  // namespace pslam::server
