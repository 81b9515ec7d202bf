#include "pslam/io/carmen_read_summary.hpp"

#include <stdexcept>

namespace pslam {

std::string DescribeUnknownTypes(const CarmenReadStats& stats) {
  std::string text;
  std::size_t named = 0;
  for (const auto& [type, count] : stats.unknown_by_type) {
    text += (text.empty() ? "" : ", ") + type + " " + std::to_string(count);
    named += count;
  }
  if (named < stats.ignored_unknown) {
    text += (text.empty() ? "" : ", ") + std::string("others ") + std::to_string(stats.ignored_unknown - named);
  }
  return text;
}

std::string DescribeReadStats(const CarmenReadStats& stats) {
  std::string text = std::to_string(stats.lines) + (stats.lines == 1 ? " line: " : " lines: ") +
                     std::to_string(stats.scans) + " scans, " + std::to_string(stats.odometry) + " ODOM, " +
                     std::to_string(stats.params) + " PARAM, " + std::to_string(stats.skipped_corrupt) + " corrupt, " +
                     std::to_string(stats.ignored_unknown) + " unknown";
  if (stats.ignored_unknown > 0) text += " (" + DescribeUnknownTypes(stats) + ")";
  return text + ", " + std::to_string(stats.dropped_late) + " out of time order";
}

void RequireScans(const CarmenReadStats& stats, const std::string& name) {
  if (stats.scans > 0) return;
  throw std::runtime_error("no laser scans in " + name + " (" + DescribeReadStats(stats) + ")");
}

}  // namespace pslam
