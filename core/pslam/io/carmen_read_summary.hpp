#pragma once
// What a CARMEN reader found in a log, in words: for run summaries, and for the error when a log
// holds no laser scans at all.
#include <string>

#include "pslam/io/carmen_reader.hpp"

namespace pslam {

// "SYNC 3, TRUEPOS 2" (by name), or "" when no record was unknown.
std::string DescribeUnknownTypes(const CarmenReadStats& stats);

// "40557 lines: 13631 scans, 26915 ODOM, 2 PARAM, 0 corrupt, 0 unknown, 0 out of time order";
// unknown records are broken down by name when there are any.
std::string DescribeReadStats(const CarmenReadStats& stats);

// Throws std::runtime_error "no laser scans in NAME (DescribeReadStats)" when the reader yielded no
// scan: mapping such a file would quietly give an empty map (a wrong file, or a log of other sensors).
void RequireScans(const CarmenReadStats& stats, const std::string& name);

}  // namespace pslam
