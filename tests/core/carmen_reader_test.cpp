#include "pslam/io/carmen_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "testing/shared_data.hpp"

namespace pslam {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// Reads every record of an in-memory log.
std::vector<LogRecord> ReadAll(const std::string& text, CarmenReaderOptions options = {},
                               CarmenReadStats* stats = nullptr) {
  std::istringstream in(text);
  CarmenReader reader(in, "test.log", options);
  std::vector<LogRecord> out;
  while (auto r = reader.Next()) out.push_back(std::move(*r));
  if (stats) *stats = reader.stats();
  return out;
}

std::vector<LaserScan> ReadScans(const std::string& text, std::size_t* without_odometry = nullptr) {
  std::istringstream in(text);
  CarmenReader reader(in, "test.log");
  ScanStream stream(reader);
  std::vector<LaserScan> out;
  while (auto s = stream.Next()) out.push_back(std::move(*s));
  if (without_odometry) *without_odometry = stream.scans_without_odometry();
  return out;
}

// The message of the CarmenParseError thrown by a strict reader, or "" if none.
std::string StrictError(const std::string& text) {
  try {
    ReadAll(text, {.strict = true});
  } catch (const CarmenParseError& e) {
    return e.what();
  }
  return "";
}

std::string Odom(double x, double y, double theta, const std::string& t) {
  std::ostringstream s;
  s << "ODOM " << x << ' ' << y << ' ' << theta << " 0.3 0.0 0.0 " << t << " host 1.0\n";
  return s.str();
}

const std::string kFlaser5 =  // protocol §4 example: laser pose 0.018 m ahead of the robot pose
    "FLASER 5 1.50 2.00 2.50 81.91 3.00 1.246728 -0.499272 0.785398 1.234000 -0.512000 0.785398 "
    "1136073618.160000 robothost 12.353000\n";

TEST(CarmenReaderTest, OdomRecord) {
  const auto records = ReadAll("ODOM 1.234000 -0.512000 0.785398 0.300000 0.100000 0.000000 1136073618.152000 robothost 12.345678\n");
  ASSERT_EQ(records.size(), 1u);
  const auto& o = std::get<OdometryReading>(records[0]);
  EXPECT_DOUBLE_EQ(o.timestamp, 1136073618.152);
  EXPECT_DOUBLE_EQ(o.pose.x, 1.234);
  EXPECT_DOUBLE_EQ(o.pose.y, -0.512);
  EXPECT_DOUBLE_EQ(o.pose.theta, 0.785398);
  EXPECT_DOUBLE_EQ(o.translational_velocity, 0.3);
  EXPECT_DOUBLE_EQ(o.rotational_velocity, 0.1);
}

TEST(CarmenReaderTest, FlaserWithPoses) {
  std::istringstream in(kFlaser5);
  CarmenReader reader(in, "test.log");
  auto record = reader.Next();
  ASSERT_TRUE(record);
  EXPECT_TRUE(reader.last_scan_has_odometry());
  const auto& s = std::get<LaserScan>(*record);
  EXPECT_EQ(s.timestamp_text, "1136073618.160000");
  EXPECT_DOUBLE_EQ(s.timestamp, 1136073618.16);
  ASSERT_EQ(s.ranges.size(), 5u);
  EXPECT_FLOAT_EQ(s.ranges[0], 1.5f);
  EXPECT_FLOAT_EQ(s.ranges[4], 3.0f);
  // 5 beams: CARMEN's "other" guess, a 180 deg fan from -90 deg.
  EXPECT_DOUBLE_EQ(s.angle_min, -kPi / 2);
  EXPECT_DOUBLE_EQ(s.angle_increment, kPi / 4);
  EXPECT_DOUBLE_EQ(s.max_range, 80.0);
  EXPECT_FALSE(s.IsReturn(3));  // 81.91 m: no echo
  EXPECT_TRUE(s.IsReturn(0));
  // Odometry is the second triple; the mount comes from laser pose vs robot pose.
  EXPECT_DOUBLE_EQ(s.odometry.x, 1.234);
  EXPECT_DOUBLE_EQ(s.odometry.y, -0.512);
  EXPECT_NEAR(s.sensor_offset.x, 0.018, 1e-5);
  EXPECT_NEAR(s.sensor_offset.y, 0.0, 1e-5);
  EXPECT_DOUBLE_EQ(s.sensor_offset.theta, 0.0);
  EXPECT_FALSE(reader.Next());
  EXPECT_DOUBLE_EQ(reader.progress(), 1.0);
}

TEST(CarmenReaderTest, Flaser180BeamsFollowsCarmenConvention) {
  std::string line = "FLASER 180";
  for (int i = 0; i < 180; ++i) line += " 1.00";
  line += " 0 0 0 0 0 0 10.0 h 0\n";
  const auto scans = ReadScans(line);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_DOUBLE_EQ(scans[0].angle_min, -90 * kDeg);
  EXPECT_DOUBLE_EQ(scans[0].angle_increment, 1 * kDeg);
  EXPECT_NEAR(scans[0].BeamAngle(179), 89 * kDeg, 1e-12);
}

TEST(CarmenReaderTest, RlaserFacesBackwardsWithParamOffset) {
  const auto scans = ReadScans(
      "PARAM robot_rearlaser_offset -0.25 1.0 host 1.0\n"
      "RLASER 3 1.0 2.0 3.0 5 5 1 5 5 1 10.0 h 0\n");
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_DOUBLE_EQ(scans[0].sensor_offset.x, -0.25);
  EXPECT_DOUBLE_EQ(scans[0].sensor_offset.theta, kPi);
}

TEST(CarmenReaderTest, PoselessFlaserUsesParamResolutionCentred) {
  CarmenReadStats stats;
  const auto records = ReadAll(
      "PARAM laser_front_laser_resolution 1.0 nohost 0\n"  // Intel-style short trailer
      "FLASER 5 1 2 3 4 5 20.5 h 0.5\n",
      {}, &stats);
  ASSERT_EQ(records.size(), 1u);
  const auto& s = std::get<LaserScan>(records[0]);
  EXPECT_EQ(s.ranges.size(), 5u);
  EXPECT_EQ(s.timestamp_text, "20.5");
  EXPECT_DOUBLE_EQ(s.angle_increment, kDeg);
  EXPECT_DOUBLE_EQ(s.angle_min, -2 * kDeg);  // a 4 deg fan is centred, not started at -90 deg
  EXPECT_EQ(stats.params, 1u);
}

TEST(CarmenReaderTest, RobotLaserTakesConfigFromRecord) {
  std::istringstream in(
      "ROBOTLASER1 0 -1.570796 3.141593 1.570796 81.900000 0.010000 1 3 1.50 2.00 2.50 2 7 8 "
      "1.246728 -0.499272 0.785398 1.234000 -0.512000 0.785398 0.300000 0.000000 0.000000 0.000000 0.000000 "
      "1136073618.160000 robothost 12.353000\n");
  CarmenReader reader(in, "test.log");
  auto record = reader.Next();
  ASSERT_TRUE(record);
  EXPECT_TRUE(reader.last_scan_has_odometry());
  const auto& s = std::get<LaserScan>(*record);
  EXPECT_EQ(s.ranges.size(), 3u);
  EXPECT_DOUBLE_EQ(s.angle_min, -1.570796);
  EXPECT_DOUBLE_EQ(s.angle_increment, 1.570796);
  EXPECT_DOUBLE_EQ(s.max_range, 81.9);
  EXPECT_DOUBLE_EQ(s.odometry.x, 1.234);
  EXPECT_NEAR(s.sensor_offset.x, 0.018, 1e-5);
  EXPECT_EQ(reader.stats().skipped_corrupt, 0u);
}

TEST(CarmenReaderTest, RawLaserHasNoOdometryAndRearMount) {
  std::istringstream in("RAWLASER2 0 -1.5 3.0 1.5 30.0 0.01 0 3 1 2 3 0 5.0 h 0\n");
  CarmenReader reader(in, "test.log");
  auto record = reader.Next();
  ASSERT_TRUE(record);
  EXPECT_FALSE(reader.last_scan_has_odometry());
  const auto& s = std::get<LaserScan>(*record);
  EXPECT_DOUBLE_EQ(s.max_range, 30.0);
  EXPECT_DOUBLE_EQ(s.angle_min, -1.5);
  EXPECT_DOUBLE_EQ(s.sensor_offset.theta, kPi);
}

TEST(CarmenReaderTest, ReordersByIpcTimestamp) {
  CarmenReadStats stats;
  const auto records = ReadAll(Odom(0, 0, 0, "3.0") + Odom(0, 0, 0, "1.0") + "FLASER 1 1.0 2.0 h 0\n" +
                                   Odom(0, 0, 0, "2.5") + Odom(0, 0, 0, "9.0") + Odom(0, 0, 0, "4.0"),
                               {}, &stats);
  std::vector<double> times;
  for (const auto& r : records) times.push_back(std::visit([](const auto& x) { return x.timestamp; }, r));
  EXPECT_EQ(times, (std::vector<double>{1.0, 2.0, 2.5, 3.0, 4.0, 9.0}));
  EXPECT_EQ(stats.dropped_late, 0u);
}

TEST(CarmenReaderTest, RecordsOlderThanTheWindowAreDropped) {
  CarmenReadStats stats;
  const auto records = ReadAll(Odom(0, 0, 0, "10.0") + Odom(0, 0, 0, "11.0") + Odom(0, 0, 0, "10.5"),
                               {.reorder_window_s = 0.0}, &stats);
  EXPECT_EQ(records.size(), 2u);
  EXPECT_EQ(stats.dropped_late, 1u);
  EXPECT_EQ(stats.skipped_corrupt, 0u);
  ASSERT_EQ(stats.first_errors.size(), 1u);
  EXPECT_EQ(stats.first_errors[0].rfind("test.log:3: ", 0), 0u) << stats.first_errors[0];
}

TEST(CarmenReaderTest, CrlfCommentsBlankAndUnknownLines) {
  CarmenReadStats stats;
  const auto records = ReadAll(
      "# CARMEN Logfile\r\n"
      "\r\n"
      "   \t\n"
      "SYNC tag 1.0 h 1.0\r\n"
      "TRUEPOS 0 0 0 0 0 0 1.0 h 0\r\n"
      "ODOM 1 2 0.5 0 0 0 1.0 h 0\r\n"
      "FLASER 1 3.5 1 2 0.5 1 2 0.5 1.5 h 0\r\n",
      {.strict = true}, &stats);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(std::get<LaserScan>(records[1]).timestamp_text, "1.5");
  EXPECT_EQ(stats.lines, 7u);
  EXPECT_EQ(stats.ignored_unknown, 2u);
  EXPECT_EQ(stats.odometry, 1u);
  EXPECT_EQ(stats.scans, 1u);
}

TEST(CarmenReaderTest, UnknownRecordsAreCountedByName) {
  std::string log = "SYNC a 1.0 h 0\nTRUEPOS 0 0 0 0 0 0 1.0 h 0\nSYNC b 2.0 h 0\n" + Odom(0, 0, 0, "1.0");
  for (int i = 0; i < 20; ++i) log += "NOISE" + std::to_string(i) + " 1.0 h 0\n";  // not a CARMEN name at all
  CarmenReadStats stats;
  ReadAll(log, {.strict = true}, &stats);
  EXPECT_EQ(stats.ignored_unknown, 23u);
  EXPECT_EQ(stats.odometry, 1u);
  EXPECT_EQ(stats.unknown_by_type.at("SYNC"), 2u);
  EXPECT_EQ(stats.unknown_by_type.at("TRUEPOS"), 1u);
  EXPECT_EQ(stats.unknown_by_type.size(), 16u);  // capped; the total still counts them all
  EXPECT_EQ(stats.unknown_by_type.count("NOISE19"), 0u);
}

TEST(CarmenReaderTest, ParamMaxRangeAndDefaults) {
  const std::string scan = "FLASER 1 60.0 0 0 0 0 0 0 1.0 h 0\n";
  auto max_range = [](const std::string& text, CarmenReaderOptions o = {}) {
    return std::get<LaserScan>(ReadAll(text, o).at(0)).max_range;
  };
  EXPECT_DOUBLE_EQ(max_range(scan), 80.0);
  EXPECT_DOUBLE_EQ(max_range(scan, {.default_max_range = 50.0}), 50.0);
  // Full trailer, short trailer and no trailer all give the value; PARAM beats the option.
  EXPECT_DOUBLE_EQ(max_range("PARAM robot_front_laser_max 40.0 1.0 h 2.0\n" + scan, {.default_max_range = 50.0}), 40.0);
  EXPECT_DOUBLE_EQ(max_range("PARAM robot_front_laser_max 41.0 h 0\n" + scan), 41.0);
  EXPECT_DOUBLE_EQ(max_range("PARAM robot_front_laser_max 42.0\n" + scan), 42.0);
  EXPECT_DOUBLE_EQ(std::get<LaserScan>(ReadAll("PARAM robot_frontlaser_offset 0.1 h 0\n" + scan).at(0)).sensor_offset.x, 0.1);
  // Values with spaces and unused keys are accepted; a PARAM without a value is corrupt.
  CarmenReadStats stats;
  ReadAll("PARAM robot_sonar_offsets 0.1 0.2 0.3 1.0 h 2.0\nPARAM robot_use_laser on\nPARAM lonely\n", {}, &stats);
  EXPECT_EQ(stats.params, 2u);
  EXPECT_EQ(stats.skipped_corrupt, 1u);
  EXPECT_EQ(StrictError("PARAM robot_front_laser_max abc 1 h 2\n"),
            "test.log:1: PARAM: robot_front_laser_max is not a number: 'abc'");
}

TEST(ScanStreamTest, InterpolatesOdometryForPoselessScans) {
  std::size_t without = 99;
  const auto scans = ReadScans("FLASER 1 1.0 0.5 h 0\n" +             // before the first ODOM: held
                               Odom(0, 0, 0, "1.0") + Odom(1, 2, 1.0, "2.0") +
                               "FLASER 1 1.0 1.25 h 0\n" +              // interpolated
                               "FLASER 1 1.0 7 8 0.1 3 4 0.2 1.5 h 0\n" +  // own robot pose
                               "RAWLASER1 0 -1.5 3.0 1.5 30.0 0.01 0 1 1 0 2.5 h 0\n",  // after the last: held
                               &without);
  ASSERT_EQ(scans.size(), 4u);
  EXPECT_DOUBLE_EQ(scans[0].timestamp, 0.5);
  EXPECT_DOUBLE_EQ(scans[0].odometry.x, 0.0);
  EXPECT_DOUBLE_EQ(scans[1].timestamp, 1.25);
  EXPECT_DOUBLE_EQ(scans[1].odometry.x, 0.25);
  EXPECT_DOUBLE_EQ(scans[1].odometry.y, 0.5);
  EXPECT_NEAR(scans[1].odometry.theta, 0.25, 1e-12);
  EXPECT_DOUBLE_EQ(scans[2].timestamp, 1.5);
  EXPECT_DOUBLE_EQ(scans[2].odometry.x, 3.0);
  EXPECT_NEAR(scans[2].odometry.theta, 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(scans[3].odometry.x, 1.0);
  EXPECT_DOUBLE_EQ(scans[3].odometry.y, 2.0);
  EXPECT_EQ(without, 0u);
}

TEST(ScanStreamTest, ScansWithoutAnyOdometryPassAtIdentity) {
  std::size_t without = 0;
  const auto scans = ReadScans("FLASER 1 1.0 0.5 h 0\nFLASER 1 1.0 30.0 h 0\n", &without);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_DOUBLE_EQ(scans[0].odometry.x, 0.0);
  EXPECT_EQ(without, 2u);
}

TEST(CarmenReaderTest, CorruptLinesStrictThrowsLenientSkips) {
  struct Case {
    std::string line, message;
  };
  const std::vector<Case> cases = {
      {"FLASER 5 1 2 3 4 0 0 0 0 0 0 1.0 h 0",
       "FLASER: n=5 needs 16 tokens (or 10 without poses), got 15"},
      {"FLASER 2 1.0 abc 0 0 0 0 0 0 1.0 h 0", "FLASER: range is not a number: 'abc'"},
      {"ODOM 1 2 3 0 0", "ODOM: needs 10 tokens (x y theta tv rv accel ipc_timestamp hostname logger_timestamp), got 6 (truncated line?)"},
      {"FLASER -3 1 2 h 0", "FLASER: negative beam count: -3"},
      {"FLASER", "FLASER: truncated line: missing beam count"},
      {"ODOM 1 2 3 0 0 0 nan h 0", "ODOM: ipc_timestamp is not finite: 'nan'"},
      {"ODOM 1 nan 3 0 0 0 1.0 h 0", "ODOM: pose is not finite: 'nan'"},
      {"ROBOTLASER1 0 -1.5 3 1.5 80 0.01 0 2 1 2 0 0 0 0 0 0 0 0 0 0 0",
       "ROBOTLASER1: needs 26 tokens (24+n+m, n=2 m=0), got 22 (truncated line?)"},
      {"ROBOTLASER1 0 -1.5 3 1.5 80 0.01 0 50 1 2", "ROBOTLASER1: n=50 but only 11 tokens (truncated line?)"},
      {"RAWLASER1 0 -1.5 3 1.5 80 0.01 0 1 1.0 0 1.0 h", "RAWLASER1: needs 14 tokens (13+n+m, n=1 m=0), got 13 (truncated line?)"},
  };
  for (const auto& c : cases) {
    const std::string log = "# header\n" + Odom(0, 0, 0, "0.5") + c.line + "\n" + Odom(0, 0, 0, "2.0");
    EXPECT_EQ(StrictError(log).rfind("test.log:3: " + c.message, 0), 0u) << StrictError(log);
    CarmenReadStats stats;
    EXPECT_EQ(ReadAll(log, {}, &stats).size(), 2u) << c.line;
    EXPECT_EQ(stats.skipped_corrupt, 1u) << c.line;
    ASSERT_EQ(stats.first_errors.size(), 1u);
    EXPECT_EQ(stats.first_errors[0].rfind("test.log:3: " + c.message, 0), 0u) << stats.first_errors[0];
  }
}

TEST(CarmenReaderTest, FirstErrorsAreCapped) {
  std::string log;
  for (int i = 0; i < 30; ++i) log += "ODOM x\n";
  CarmenReadStats stats;
  ReadAll(log, {}, &stats);
  EXPECT_EQ(stats.skipped_corrupt, 30u);
  EXPECT_EQ(stats.first_errors.size(), 20u);
}

TEST(CarmenReaderTest, NanAndNegativeRangesAreKept) {
  CarmenReadStats stats;
  const auto records = ReadAll("FLASER 3 nan -1.0 inf 0 0 0 0 0 0 1.0 h 0\n", {.strict = true}, &stats);
  ASSERT_EQ(records.size(), 1u);
  const auto& s = std::get<LaserScan>(records[0]);
  ASSERT_EQ(s.ranges.size(), 3u);
  EXPECT_TRUE(std::isnan(s.ranges[0]));
  EXPECT_FLOAT_EQ(s.ranges[1], -1.0f);
  EXPECT_TRUE(std::isinf(s.ranges[2]));
  for (std::size_t i = 0; i < 3; ++i) EXPECT_FALSE(s.IsReturn(i));
  EXPECT_EQ(stats.skipped_corrupt, 0u);
}

TEST(CarmenReaderTest, OpensFilesAndNamesMissingOnes) {
  const auto path = std::filesystem::temp_directory_path() / "pslam_carmen_reader_test.log";
  { std::ofstream(path) << Odom(0, 0, 0, "1.0") << kFlaser5; }
  CarmenReader reader(path.string());
  EXPECT_DOUBLE_EQ(reader.progress(), 0.0);
  std::size_t n = 0;
  while (reader.Next()) ++n;
  EXPECT_EQ(n, 2u);
  EXPECT_DOUBLE_EQ(reader.progress(), 1.0);
  std::filesystem::remove(path);

  try {
    CarmenReader missing("/nonexistent/dir/log.clf");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/log.clf"), std::string::npos) << e.what();
  }
}

TEST(CarmenReaderIntelTest, ReadsTheWholeLogInTimeOrder) {
  PSLAM_REQUIRE_DATA(path, "intel/intel.clf");
  CarmenReader reader(path.string());
  ScanStream stream(reader);
  std::size_t count = 0, no_echo = 0;
  double last = -1.0;
  std::string first_text;
  while (auto scan = stream.Next()) {
    if (count == 0) first_text = scan->timestamp_text;
    ++count;
    ASSERT_EQ(scan->ranges.size(), 180u);
    ASSERT_GT(scan->timestamp, last) << scan->timestamp_text;
    last = scan->timestamp;
    for (std::size_t i = 0; i < scan->ranges.size(); ++i)
      if (std::abs(scan->ranges[i] - 81.83f) < 1e-3f) {
        ++no_echo;
        ASSERT_FALSE(scan->IsReturn(i));  // 81.83 marks no return: beyond the 80 m max range
      }
  }
  const CarmenReadStats& stats = reader.stats();
  EXPECT_EQ(count, 13631u);
  EXPECT_EQ(first_text, "976052857.337530");
  EXPECT_EQ(no_echo, 68313u);
  EXPECT_EQ(stats.scans, 13631u);
  EXPECT_EQ(stats.odometry, 26915u);
  EXPECT_EQ(stats.params, 2u);
  EXPECT_EQ(stats.lines, 40557u);
  EXPECT_EQ(stats.skipped_corrupt, 0u);
  EXPECT_EQ(stats.dropped_late, 0u);
  EXPECT_EQ(stream.scans_without_odometry(), 0u);
  EXPECT_DOUBLE_EQ(reader.progress(), 1.0);
}

}  // namespace
}  // namespace pslam
