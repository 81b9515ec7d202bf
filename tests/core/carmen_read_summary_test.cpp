// What a reader found in a log, in words, and the error for a log without laser scans.
#include "pslam/io/carmen_read_summary.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "pslam/experiment/log_run.hpp"
#include "pslam/io/carmen_reader.hpp"

namespace pslam {
namespace {

CarmenReadStats ReadToEnd(const std::string& text) {
  std::istringstream in(text);
  CarmenReader reader(in, "test.clf");
  while (reader.Next()) {
  }
  return reader.stats();
}

const std::string kNoScans =
    "# CARMEN Logfile\n"
    "PARAM robot_frontlaser_offset 0.0 nohost 0.0\n"
    "ODOM 0 0 0 0 0 0 1.0 nohost 0.0\n"
    "SYNC x 1.5 nohost 0.5\n"
    "FLASER 180 1.0 2.0\n";  // cut off: corrupt, not a scan

TEST(CarmenReadSummary, DescribesWhatTheReaderFound) {
  const CarmenReadStats stats = ReadToEnd(kNoScans + "SYNC y 2.0 nohost 1.0\nTRUEPOS 0 0 0 0 0 0 2.0 nohost 1.0\n");
  EXPECT_EQ(DescribeReadStats(stats),
            "7 lines: 0 scans, 1 ODOM, 1 PARAM, 1 corrupt, 3 unknown (SYNC 2, TRUEPOS 1), 0 out of time order");
  EXPECT_EQ(DescribeUnknownTypes(ReadToEnd("ODOM 0 0 0 0 0 0 1.0 nohost 0.0\n")), "");
}

TEST(CarmenReadSummary, ALogWithoutScansIsAnError) {
  try {
    RequireScans(ReadToEnd(kNoScans), "test.clf");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(),
                 "no laser scans in test.clf (5 lines: 0 scans, 1 ODOM, 1 PARAM, 1 corrupt, 1 unknown (SYNC 1), "
                 "0 out of time order)");
  }
  EXPECT_NO_THROW(RequireScans(ReadToEnd(kNoScans + "FLASER 1 2.0 2.0 nohost 1.0\n"), "test.clf"));
}

TEST(CarmenReadSummary, MappingALogWithoutScansFails) {
  const auto path =
      std::filesystem::path(::testing::TempDir()) / ("pslam_no_scans_" + std::to_string(getpid()) + ".clf");
  std::ofstream(path) << kNoScans;
  EXPECT_THROW(RunLog(path.string(), PSlamOptions{}), std::runtime_error);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace pslam
