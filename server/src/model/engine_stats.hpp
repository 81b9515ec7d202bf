#pragma once
// A session engine's running statistics, as plain data (live view, REST, checkpoints).
#include <cstddef>
#include <cstdint>

namespace pslam::server {

struct EngineStats {
  std::int64_t processed_seq = 0;
  std::int64_t scans = 0;
  std::int64_t updates = 0;
  std::int64_t resamplings = 0;
  int particles = 0;
  double neff = 0.0;
  double scan_rate_hz = 0.0;       // scans processed per second over the last few seconds
  double latency_ms_mean = 0.0;    // input received -> processed by the filter, recent mean
  double latency_ms_max = 0.0;     // recent maximum
  double step_ms_mean = 0.0;       // filter time per scan, recent mean
  std::size_t queued = 0;          // inputs waiting for the filter
  bool rebuilding = false;         // re-running stored inputs after a restart
};

}  // namespace pslam::server
