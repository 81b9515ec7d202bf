// The real-robot source end to end on pseudo-terminals: both device simulators, scans stamped on
// arrival with odometry interpolated from the SIPs around them.
#include "sources/pioneer_source.hpp"

#include <gtest/gtest.h>

#include "fakes/fake_pioneer.hpp"
#include "fakes/fake_sick.hpp"
#include "sources/odometry_interpolator.hpp"

namespace pslam::agent {
namespace {

TEST(OdometryInterpolatorTest, WaitsForLaterOdometryThenInterpolates) {
  OdometryInterpolator interp(0.5);
  interp.AddOdometry({10.0, Pose2D(0, 0, 0), 0, 0});
  LaserScan scan;
  scan.timestamp = 10.025;
  interp.AddScan(scan);
  EXPECT_FALSE(interp.NextReady(10.03));  // no odometry after the scan yet
  interp.AddOdometry({10.1, Pose2D(1.0, 0, 0.4), 0, 0});
  const auto ready = interp.NextReady(10.1);
  ASSERT_TRUE(ready);
  EXPECT_NEAR(ready->odometry.x, 0.25, 1e-12);
  EXPECT_NEAR(ready->odometry.theta, 0.1, 1e-12);
  EXPECT_EQ(interp.held_scans(), 0u);
}

TEST(OdometryInterpolatorTest, StalledOdometryHoldsTheLastReading) {
  OdometryInterpolator interp(0.5);
  interp.AddOdometry({10.0, Pose2D(2, 0, 0), 0, 0});
  LaserScan scan;
  scan.timestamp = 10.2;
  interp.AddScan(scan);
  EXPECT_FALSE(interp.NextReady(10.5));
  const auto ready = interp.NextReady(10.8);
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->odometry.x, 2.0);
  EXPECT_EQ(interp.held_scans(), 1u);
}

TEST(PioneerSourceTest, StreamsInterpolatedScansAndDrives) {
  testing::FakePioneer robot;
  testing::FakeSick laser;
  PioneerSourceOptions o;
  o.robot_device = robot.device();
  o.laser_device = laser.device();
  o.robot.probe_bauds = {9600};
  o.laser.probe_timeout_s = 0.3;
  PioneerSource source(o);
  EXPECT_EQ(source.laser().beams, 181u);
  EXPECT_DOUBLE_EQ(source.laser().offset.x, 0.018);
  source.Drive({0.3, 0.0});
  std::size_t scans = 0, odometry = 0;
  double last_scan_t = 0, last_x = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < end) {
    auto e = source.Next(0.1);
    if (!e) continue;
    if (auto* s = std::get_if<LaserScan>(&*e)) {
      ++scans;
      EXPECT_GT(s->timestamp, last_scan_t);
      EXPECT_GE(s->odometry.x, last_x - 1e-9);  // moving forward: interpolated odometry never goes back
      last_scan_t = s->timestamp;
      last_x = s->odometry.x;
    } else {
      ++odometry;
    }
  }
  EXPECT_GT(scans, 100u);  // 75 Hz
  EXPECT_GE(odometry, 15u);  // 10 Hz
  EXPECT_GT(last_x, 0.2);
  EXPECT_NE(source.StatsLine().find("0 bad CRC"), std::string::npos) << source.StatsLine();
  source.Shutdown();
}

}  // namespace
}  // namespace pslam::agent
