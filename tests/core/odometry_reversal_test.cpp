#include "pslam/io/odometry_reversal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "pslam/eval/relative_pose_error.hpp"
#include "pslam/io/carmen_reader.hpp"
#include "testing/shared_data.hpp"

namespace pslam {
namespace {

std::string Odom(double x, double y, double theta, double tv, double t) {
  std::ostringstream s;
  s.precision(10);
  s << "ODOM " << x << ' ' << y << ' ' << theta << ' ' << tv << " 0.0 0.0 " << t << " host " << t << '\n';
  return s.str();
}

std::string Flaser(double x, double y, double theta, double t) {
  std::ostringstream s;
  s.precision(10);
  s << "FLASER 3 1.0 2.0 3.0 " << x << ' ' << y << ' ' << theta << ' ' << x << ' ' << y << ' ' << theta << ' ' << t
    << " host " << t << '\n';
  return s.str();
}

struct Read {
  std::vector<Pose2D> odometry, scans;
  std::size_t repaired = 0;
};

Read ReadLog(const std::string& text, bool repair = true) {
  std::istringstream in(text);
  CarmenReader reader(in, "test.log", {.repair_reversed_odometry = repair});
  Read out;
  while (auto record = reader.Next()) {
    if (const auto* odom = std::get_if<OdometryReading>(&*record)) {
      out.odometry.push_back(odom->pose);
    } else {
      out.scans.push_back(std::get<LaserScan>(*record).odometry);
    }
  }
  out.repaired = reader.stats().repaired_odometry_steps;
  return out;
}

// The robot drives 1 m east, then backs up 0.6 m at -0.5 m/s; the recorder logs the backing up as
// 0.6 m more to the east, as the Freiburg 079 log does.
std::string BackingUpLoggedForward() {
  std::string log;
  double x = 0.0, t = 0.0;
  for (int i = 0; i < 10; ++i, t += 0.2, x += 0.1) log += Odom(x, 0.0, 0.0, 0.5, t) + Flaser(x + 0.05, 0.0, 0.0, t + 0.1);
  log += Odom(x, 0.0, 0.0, 0.0, t);  // stopped at 1 m
  t += 0.2;
  for (int i = 0; i < 6; ++i, t += 0.2) {
    x += 0.1;  // logged forward ...
    log += Flaser(x - 0.05, 0.0, 0.0, t - 0.1) + Odom(x, 0.0, 0.0, -0.5, t);  // ... at a backward velocity
  }
  return log;
}

TEST(OdometryReversalTest, BackingUpLoggedForwardIsIntegratedBackwards) {
  const Read read = ReadLog(BackingUpLoggedForward());
  EXPECT_EQ(read.repaired, 6u);
  ASSERT_EQ(read.odometry.size(), 17u);
  EXPECT_NEAR(read.odometry[10].x, 1.0, 1e-9);  // forward driving is untouched
  EXPECT_NEAR(read.odometry.back().x, 0.4, 1e-9);
  EXPECT_NEAR(read.odometry.back().y, 0.0, 1e-9);
  // A scan half-way through the last backward step lies between the repaired poses.
  EXPECT_NEAR(read.scans.back().x, 0.45, 1e-9);
  for (std::size_t i = 11; i < read.odometry.size(); ++i) EXPECT_LT(read.odometry[i].x, read.odometry[i - 1].x);
}

TEST(OdometryReversalTest, RawOdometryOnRequest) {
  const Read read = ReadLog(BackingUpLoggedForward(), /*repair=*/false);
  EXPECT_EQ(read.repaired, 0u);
  EXPECT_NEAR(read.odometry.back().x, 1.6, 1e-9);
}

TEST(OdometryReversalTest, ConsistentOdometryPassesBitForBit) {
  // Backing up logged as backing up, turning on the spot at zero velocity, and a reversal of
  // direction without stopping (velocities of both signs): nothing to repair.
  std::string log;
  double x = 0.0, t = 0.0;
  for (int i = 0; i < 5; ++i, t += 0.2, x -= 0.1) log += Odom(x, 0.01 * i, 0.1 * i, -0.5, t);
  log += Odom(x, 0.05, 0.6, 0.0, t) + Odom(x + 0.05, 0.05, 0.7, 0.4, t + 0.2);
  log += Odom(x + 0.1, 0.05, 0.8, -0.4, t + 0.4) + Flaser(x + 0.08, 0.05, 0.8, t + 0.5);
  const Read repaired = ReadLog(log), raw = ReadLog(log, false);
  EXPECT_EQ(repaired.repaired, 0u);
  ASSERT_EQ(repaired.odometry.size(), raw.odometry.size());
  for (std::size_t i = 0; i < raw.odometry.size(); ++i) {
    EXPECT_EQ(repaired.odometry[i].x, raw.odometry[i].x);
    EXPECT_EQ(repaired.odometry[i].y, raw.odometry[i].y);
    EXPECT_EQ(repaired.odometry[i].theta, raw.odometry[i].theta);
  }
  EXPECT_EQ(repaired.scans.front().x, raw.scans.front().x);
}

// Odometry alone against the ground truth of Kümmerle et al. over relations at most 3 s long:
// how many of them it gets wrong by more than 0.3 m.
std::size_t ShortRelationsOffBy30cm(const std::filesystem::path& log, const std::filesystem::path& relations,
                                    bool repair) {
  CarmenReader reader(log.string(), {.repair_reversed_odometry = repair});
  ScanStream scans(reader);
  std::vector<StampedPose> trajectory;
  while (auto scan = scans.Next()) {
    trajectory.push_back({scan->timestamp_text, scan->timestamp, scan->odometry * scan->sensor_offset});
  }
  std::size_t off = 0;
  for (const Relation& relation : ReadRelations(relations.string())) {
    if (std::stod(relation.stamp2) - std::stod(relation.stamp1) > 3.0) continue;
    if (ComputeRpe(trajectory, {relation}).trans_mean > 0.3) ++off;
  }
  return off;
}

TEST(OdometryReversalTest, Fr079OdometryAgreesWithGroundTruthWhenBackingUp) {
  PSLAM_REQUIRE_DATA(log, "fr079/fr079.clf");
  PSLAM_REQUIRE_DATA(relations, "fr079/fr079.relations");
  // As logged, the robot backing up shows as driving on: 30 short relations are off by > 0.3 m.
  EXPECT_GT(ShortRelationsOffBy30cm(log, relations, false), 20u);
  EXPECT_EQ(ShortRelationsOffBy30cm(log, relations, true), 0u);
}

}  // namespace
}  // namespace pslam
