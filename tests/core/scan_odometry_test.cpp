// Scan odometry: wheel odometry corrected by matching each scan against the scans before it.
#include "pslam/localize/scan_odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "testing/synthetic_world.hpp"

namespace pslam {
namespace {

using testing::RenderScan;
using testing::RoomWalls;

// True poses along y = -1.5 from x = -3.5 to 3.5, a quarter turn on the spot, then up to y = 2.5.
std::vector<Pose2D> Route() {
  std::vector<Pose2D> route;
  for (double x = -3.5; x <= 3.5 + 1e-9; x += 0.05) route.emplace_back(x, -1.5, 0.0);
  for (double turn = 0.05; turn <= std::numbers::pi / 2 + 1e-9; turn += 0.05) route.emplace_back(3.5, -1.5, turn);
  for (double y = -1.45; y <= 2.5 + 1e-9; y += 0.05) route.emplace_back(3.5, y, std::numbers::pi / 2);
  return route;
}

// Wheels that overstate distance by 10 % and drift 0.03 rad per metre driven.
std::vector<Pose2D> BiasedOdometry(const std::vector<Pose2D>& route) {
  std::vector<Pose2D> odometry{route.front()};
  for (std::size_t i = 1; i < route.size(); ++i) {
    const Pose2D step = Between(route[i - 1], route[i]);
    const double length = std::hypot(step.x, step.y);
    odometry.push_back(odometry.back() * Pose2D(1.1 * step.x, 1.1 * step.y, step.theta + 0.03 * length));
  }
  return odometry;
}

double PositionError(const Pose2D& estimate_start, const Pose2D& estimate_end, const Pose2D& true_start,
                     const Pose2D& true_end) {
  const Pose2D estimated = Between(estimate_start, estimate_end), truth = Between(true_start, true_end);
  return std::hypot(estimated.x - truth.x, estimated.y - truth.y);
}

TEST(ScanOdometryTest, FollowsTheTrueMotionWhereTheWheelsOverstateAndDrift) {
  const auto walls = RoomWalls();
  const std::vector<Pose2D> route = Route();
  const std::vector<Pose2D> odometry = BiasedOdometry(route);
  ScanOdometry scan_odometry(ScanOdometryOptions{.enabled = true, .scans_per_map = 20});
  std::vector<Pose2D> corrected;
  for (std::size_t i = 0; i < route.size(); ++i) corrected.push_back(scan_odometry.Correct(RenderScan(route[i], walls, odometry[i])));

  const double wheel_error = PositionError(odometry.front(), odometry.back(), route.front(), route.back());
  const double corrected_error = PositionError(corrected.front(), corrected.back(), route.front(), route.back());
  EXPECT_GT(wheel_error, 0.8);  // the scenario's wheels are far off
  EXPECT_LT(corrected_error, 0.1) << "wheels " << wheel_error << " m off";
  const double heading_error = NormalizeAngle(Between(corrected.front(), corrected.back()).theta - std::numbers::pi / 2);
  EXPECT_LT(std::abs(heading_error), 0.02);
}

TEST(ScanOdometryTest, TheFirstScanKeepsItsOdometryAndNoReturnsFallBackOnTheWheels) {
  ScanOdometry scan_odometry(ScanOdometryOptions{.enabled = true});
  const Pose2D start(1.0, 2.0, 0.3);
  const Pose2D first = scan_odometry.Correct(RenderScan(Pose2D(), RoomWalls(), start));
  EXPECT_DOUBLE_EQ(first.x, start.x);
  EXPECT_DOUBLE_EQ(first.y, start.y);
  EXPECT_DOUBLE_EQ(first.theta, start.theta);
  // A scan that sees nothing cannot be matched: the wheels' motion carries the pose.
  LaserScan blind = RenderScan(Pose2D(), {}, start * Pose2D(0.2, 0.0, 0.1));
  const Pose2D next = scan_odometry.Correct(blind);
  const Pose2D moved = Between(first, next);
  EXPECT_NEAR(moved.x, 0.2, 1e-9);
  EXPECT_NEAR(moved.y, 0.0, 1e-9);
  EXPECT_NEAR(moved.theta, 0.1, 1e-9);
}

}  // namespace
}  // namespace pslam
