#pragma once
// Wall-clock time as stored in the database (Unix seconds, fractional) and a monotonic clock for
// latencies, kept apart so a clock step never makes a latency negative.
#include <chrono>

namespace pslam::server {

inline double UnixNow() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

using SteadyTime = std::chrono::steady_clock::time_point;
inline SteadyTime SteadyNow() { return std::chrono::steady_clock::now(); }
inline double SecondsSince(SteadyTime start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace pslam::server
