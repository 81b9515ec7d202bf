#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "drive/path_frames.hpp"
#include "drive/safety.hpp"
#include "drive/stall_recovery.hpp"

namespace pslam::agent {
namespace {

LaserScan WallAhead(double distance, double lateral_half_width = 0.3) {
  LaserScan scan;
  scan.angle_min = -std::numbers::pi / 2;
  scan.angle_increment = std::numbers::pi / 180;
  scan.max_range = 8.0;
  for (int i = 0; i < 181; ++i) {
    const double a = scan.BeamAngle(static_cast<std::size_t>(i));
    // A short wall segment across the path at x = distance, |y| <= lateral_half_width.
    const double r = std::cos(a) > 1e-6 ? distance / std::cos(a) : 100.0;
    scan.ranges.push_back(std::abs(r * std::sin(a)) <= lateral_half_width ? static_cast<float>(r) : 8.0f);
  }
  return scan;
}

TEST(PathFramesTest, MapPathIsMovedIntoTheOdometryFrame) {
  // The robot is at (1, 1, 90 deg) in the map but (0, 0, 0) in its odometry: map +y is odometry +x.
  const auto path = MapPathToOdometry({{1, 1}, {1, 3}}, Pose2D(1, 1, std::numbers::pi / 2), Pose2D(0, 0, 0));
  EXPECT_NEAR(path[0].x(), 0, 1e-12);
  EXPECT_NEAR(path[1].x(), 2, 1e-12);
  EXPECT_NEAR(path[1].y(), 0, 1e-12);
}

TEST(SafetyTest, ObstacleAheadStopsForwardMotionButAllowsTurning) {
  SafetyMonitor safety;
  safety.OnScan(WallAhead(0.45), 10.0);
  const auto d = safety.Filter({0.3, 0.2}, 10.01, 10.0);
  EXPECT_EQ(d.reason, StopReason::kObstacle);
  EXPECT_EQ(d.command.v, 0.0);
  EXPECT_EQ(d.command.w, 0.2);
  EXPECT_NEAR(safety.free_distance_ahead_m(), 0.45, 1e-3);
}

TEST(SafetyTest, FarOrSideObstaclesDoNotStop) {
  SafetyMonitor safety;
  safety.OnScan(WallAhead(2.0), 10.0);
  EXPECT_EQ(safety.Filter({0.3, 0}, 10.01, 10.0).reason, StopReason::kNone);
  LaserScan side = WallAhead(100.0);
  side.ranges[180] = 0.3f;  // 30 cm to the left, beside the robot
  safety.OnScan(side, 10.0);
  EXPECT_EQ(safety.Filter({0.3, 0}, 10.01, 10.0).reason, StopReason::kNone);
}

TEST(SafetyTest, StoppingDistanceGrowsWithSpeed) {
  SafetyMonitor safety;
  safety.OnScan(WallAhead(0.6), 10.0);
  EXPECT_EQ(safety.Filter({0.05, 0}, 10.01, 10.0).reason, StopReason::kNone);
  EXPECT_EQ(safety.Filter({0.5, 0}, 10.01, 10.0).reason, StopReason::kObstacle);
}

TEST(SafetyTest, LostLinkAndStaleLaserStopEverything) {
  SafetyMonitor safety;
  safety.OnScan(WallAhead(5.0), 10.0);
  auto d = safety.Filter({0.3, 0.5}, 11.6, 10.0);  // server silent for 1.6 s > 1.5 s
  EXPECT_EQ(d.reason, StopReason::kLinkLost);
  EXPECT_EQ(d.command, VelocityCommand{});
  d = safety.Filter({0.3, 0.5}, 10.6, 10.5);  // laser silent for 0.6 s
  EXPECT_EQ(d.reason, StopReason::kNoScan);
  EXPECT_EQ(d.command, VelocityCommand{});
}

TEST(StallRecoveryTest, ARobotThatDoesNotMoveWhenToldToBacksOffThenDrivesAgain) {
  StallRecovery stall;  // 2 s without 2 cm of progress, then 1.5 s backing off at 0.1 m/s
  const VelocityCommand forward{0.2, 0.1};
  const Pose2D pinned(1.0, 2.0, 0.5);
  double t = 0.0;
  for (; t < 1.95; t += 0.1) EXPECT_EQ(stall.Filter(forward, pinned, t), forward) << t;
  const VelocityCommand back = stall.Filter(forward, pinned, 2.05);
  EXPECT_LT(back.v, 0.0);
  EXPECT_EQ(back.w, 0.0);
  EXPECT_EQ(stall.stalls(), 1);
  EXPECT_TRUE(stall.backing_off(3.0));
  EXPECT_LT(stall.Filter(forward, pinned, 3.4).v, 0.0);
  EXPECT_EQ(stall.Filter(forward, Pose2D(0.85, 2.0, 0.5), 3.6), forward);  // done: forward again
  EXPECT_TRUE(stall.careful(10.0));
  EXPECT_FALSE(stall.careful(14.0));
}

TEST(StallRecoveryTest, SlowProgressStandingAndTurningInPlaceAreNoStall) {
  StallRecovery stall;
  const VelocityCommand forward{0.2, 0.0}, turn{0.0, 0.8};
  for (int i = 0; i < 100; ++i) {  // 10 s at 1.5 cm/s: slow, but moving
    EXPECT_EQ(stall.Filter(forward, Pose2D(0.0015 * i, 0.0, 0.0), 0.1 * i), forward) << i;
  }
  for (int i = 0; i < 100; ++i) EXPECT_EQ(stall.Filter(turn, Pose2D(0.2, 0.0, 0.08 * i), 10.0 + 0.1 * i), turn);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(stall.Filter({}, Pose2D(0.2, 0.0, 0.0), 20.0 + 0.1 * i), VelocityCommand{});
  EXPECT_EQ(stall.stalls(), 0);
}

TEST(StallRecoveryTest, AResetEndsTheBackOff) {
  StallRecovery stall;
  const VelocityCommand forward{0.2, 0.0};
  for (double t = 0.0; t < 2.2; t += 0.1) stall.Filter(forward, Pose2D(), t);
  ASSERT_TRUE(stall.backing_off(2.3));
  stall.Reset();  // the link was lost: the safety layer stops the robot, and the back-off is over
  EXPECT_FALSE(stall.backing_off(2.3));
  EXPECT_EQ(stall.Filter(forward, Pose2D(), 2.4), forward);
}

}  // namespace
}  // namespace pslam::agent
