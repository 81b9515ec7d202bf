// Differential-drive kinematics, acceleration limits and collisions of the simulated P3-DX.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "pslam/sim/diff_drive.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Noise-free options with instant acceleration: the robot does exactly what it is told.
SimulatorOptions Exact() {
  SimulatorOptions o;
  o.drive.max_linear_acceleration = kInf;
  o.drive.max_angular_acceleration = kInf;
  o.odometry_noise = {0.0, 0.0, 0.0, 0.0, 0.0};
  o.laser.range_noise_stddev = 0.0;
  return o;
}

World BigRoom() { return MakeWalledRoom(20.0, 20.0, 0.1, 0.05); }

TEST(SimKinematicsTest, IntegrateArcFollowsTheCircle) {
  // v = 0.2 m/s, w = 0.5 rad/s: a circle of radius 0.4 m; after pi seconds the robot has turned
  // 90 degrees and sits at (0.4, 0.4) from a start at the origin facing +x.
  const Pose2D end = IntegrateArc(Pose2D(0, 0, 0), {0.2, 0.5}, std::numbers::pi);
  EXPECT_NEAR(end.x, 0.4, 1e-12);
  EXPECT_NEAR(end.y, 0.4, 1e-12);
  EXPECT_NEAR(end.theta, std::numbers::pi / 2.0, 1e-12);
  const Pose2D straight = IntegrateArc(Pose2D(1, 2, std::numbers::pi / 2.0), {0.2, 0.0}, 3.0);
  EXPECT_NEAR(straight.x, 1.0, 1e-12);
  EXPECT_NEAR(straight.y, 2.6, 1e-12);
}

TEST(SimKinematicsTest, SimulatorIntegratesAKnownCommandExactly) {
  Simulator sim(BigRoom(), Pose2D(10.0, 10.0, 0.3), Exact());
  sim.SetCommand({0.2, 0.5});
  for (int i = 0; i < 40; ++i) sim.Step(0.1);  // 4 s, in 400 physics ticks
  const Pose2D expected = IntegrateArc(Pose2D(10.0, 10.0, 0.3), {0.2, 0.5}, 4.0);
  EXPECT_NEAR(sim.true_pose().x, expected.x, 1e-9);
  EXPECT_NEAR(sim.true_pose().y, expected.y, 1e-9);
  EXPECT_NEAR(sim.true_pose().theta, expected.theta, 1e-9);
  EXPECT_NEAR(sim.time(), 4.0, 1e-9);
  // Without noise the odometry is the truth.
  EXPECT_NEAR(sim.odometry_pose().x, expected.x, 1e-9);
  EXPECT_NEAR(sim.odometry_pose().y, expected.y, 1e-9);
  EXPECT_NEAR(sim.odometry_pose().theta, expected.theta, 1e-9);
}

TEST(SimKinematicsTest, CommandsAreClampedToTheSpeedLimits) {
  Simulator sim(BigRoom(), Pose2D(10.0, 10.0, 0.0), Exact());
  sim.SetCommand({1.0, 10.0});
  EXPECT_DOUBLE_EQ(sim.command().linear, 0.2);
  EXPECT_NEAR(sim.command().angular, 100.0 * std::numbers::pi / 180.0, 1e-12);
}

TEST(SimKinematicsTest, AccelerationIsLimited) {
  SimulatorOptions options = Exact();
  options.drive.max_linear_acceleration = 0.3;
  Simulator sim(BigRoom(), Pose2D(10.0, 10.0, 0.0), options);
  sim.SetCommand({0.2, 0.0});
  sim.Step(0.5);
  EXPECT_NEAR(sim.velocity().linear, 0.15, 1e-9);  // 0.3 m/s^2 for 0.5 s
  sim.Step(0.5);
  EXPECT_NEAR(sim.velocity().linear, 0.2, 1e-9);
  // Ramp 0 -> 0.2 m/s takes 2/3 s and covers 1/15 m; the remaining 1/3 s at 0.2 m/s covers 1/15 m.
  EXPECT_NEAR(sim.true_pose().x, 10.0 + 2.0 / 15.0, 2e-3);  // up to the tick discretisation
}

TEST(SimKinematicsTest, CollisionStopsTheRobotAndIsReported) {
  Simulator sim(BigRoom(), Pose2D(18.0, 10.0, 0.0), Exact());  // the wall at x = 20, 2 m ahead
  sim.SetCommand({0.2, 0.0});
  bool collided = false;
  for (int i = 0; i < 200 && !collided; ++i) collided = sim.Step(0.1).collided;
  ASSERT_TRUE(collided);
  EXPECT_EQ(sim.collision_count(), 1u);
  // Stopped before touching: the disc edge within one 2 mm tick of the wall.
  EXPECT_LE(sim.true_pose().x, 20.0 - 0.25 + 1e-9);
  EXPECT_GT(sim.true_pose().x, 20.0 - 0.25 - 0.003);
  EXPECT_EQ(sim.velocity().linear, 0.0);
  EXPECT_EQ(sim.command().linear, 0.0);  // the command is cancelled ...
  const double x = sim.true_pose().x;
  EXPECT_FALSE(sim.Step(1.0).collided);  // ... so the robot stays put
  EXPECT_EQ(sim.true_pose().x, x);
  // It may still turn and drive away.
  sim.SetCommand({0.0, 1.0});
  EXPECT_FALSE(sim.Step(std::numbers::pi).collided);
  sim.SetCommand({0.2, 0.0});
  EXPECT_FALSE(sim.Step(1.0).collided);
  EXPECT_LT(sim.true_pose().x, x - 0.15);
}

TEST(SimKinematicsTest, StartInsideAnObstacleIsRejected) {
  EXPECT_THROW({ Simulator sim(BigRoom(), Pose2D(0.1, 10.0, 0.0)); }, std::invalid_argument);
}

}  // namespace
}  // namespace pslam
