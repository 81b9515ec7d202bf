#pragma once
// Maps the first scans of a CARMEN log with a filter, for tests on slices of the real logs.
#include <string>
#include <vector>

#include "pslam/eval/trajectory_io.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/io/carmen_reader.hpp"

namespace pslam {

// Feeds the first `scans` scans of `log` to `filter` and returns the filter's trajectory at each.
inline std::vector<StampedPose> MapLogSlice(const std::string& log, Rbpf& filter, int scans) {
  CarmenReader reader(log);
  ScanStream stream(reader);
  std::vector<std::string> stamps;
  while (auto scan = stream.Next()) {
    if (static_cast<int>(stamps.size()) == scans) break;
    stamps.push_back(scan->timestamp_text);
    filter.AddScan(*scan);
  }
  filter.FlushLoopClosure();
  const std::vector<Pose2D> poses = filter.Trajectory();
  std::vector<StampedPose> out;
  for (std::size_t i = 0; i < poses.size(); ++i) out.push_back({stamps[i], 0.0, poses[i]});
  return out;
}

}  // namespace pslam
