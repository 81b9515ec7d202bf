// World queries, exact ray casting and the LMS-200 model against tiny synthetic worlds.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pslam/sim/laser_model.hpp"
#include "pslam/sim/ray_cast.hpp"
#include "pslam/sim/world.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

constexpr double kRes = 0.05;
constexpr double kPi = std::numbers::pi;

// A 10 m x 6 m room, walls outside [0, 10] x [0, 6].
World Room() { return MakeWalledRoom(10.0, 6.0, 0.1, kRes); }

TEST(SimWorldTest, WalledRoomHasFreeInteriorAndOccupiedWalls) {
  const World world = Room();
  EXPECT_TRUE(world.IsFree(world.WorldToCell({5.0, 3.0})));
  EXPECT_TRUE(world.IsFree(world.WorldToCell({0.01, 0.01})));
  EXPECT_TRUE(world.IsOccupied(world.WorldToCell({-0.01, 3.0})));
  EXPECT_TRUE(world.IsOccupied(world.WorldToCell({10.06, 3.0})));
  EXPECT_EQ(world.At(world.WorldToCell({-1.0, 3.0})), WorldCell::kUnknown);  // beyond the bounds
  EXPECT_EQ(world.Count(WorldCell::kFree), 200u * 120u);
  // The walls' outer faces bound it.
  EXPECT_TRUE(world.Extent().isApprox(Eigen::AlignedBox2d(Eigen::Vector2d(-0.1, -0.1), Eigen::Vector2d(10.1, 6.1))));
}

TEST(SimWorldTest, DiscFreeIsExactAgainstWalls) {
  const World world = Room();
  EXPECT_TRUE(world.IsDiscFree({0.26, 3.0}, 0.25));
  EXPECT_FALSE(world.IsDiscFree({0.24, 3.0}, 0.25));
  EXPECT_TRUE(world.IsDiscFree({5.0, 5.74}, 0.25));
  EXPECT_FALSE(world.IsDiscFree({5.0, 5.76}, 0.25));
}

TEST(SimWorldTest, GridRoundTripKeepsEveryCell) {
  const World world = Room();
  const World back = World::FromGrid(world.ToGrid());
  ASSERT_EQ(back.bounds().min, world.bounds().min);
  ASSERT_EQ(back.bounds().max, world.bounds().max);
  EXPECT_EQ(back.Count(WorldCell::kOccupied), world.Count(WorldCell::kOccupied));
  EXPECT_EQ(back.Count(WorldCell::kFree), world.Count(WorldCell::kFree));
}

TEST(SimRayCastTest, HitsTheCellBoundaryExactly) {
  World world = Room();
  FillBox(world, {4.0, 0.0}, {4.5, 6.0}, WorldCell::kOccupied);  // a wall across the room at x = 4
  EXPECT_NEAR(CastRay(world, {2.0, 3.0}, 0.0, 8.0), 2.0, 1e-9);
  // At 60 degrees off the wall's normal the ray travels 2 / cos(60) = 4 m.
  EXPECT_NEAR(CastRay(world, {2.0, 1.0}, kPi / 3.0, 8.0), 4.0, 1e-9);
  // Away from the wall: the far wall at x = 0.
  EXPECT_NEAR(CastRay(world, {2.0, 3.0}, kPi, 8.0), 2.0, 1e-9);
  // Up to the top wall at y = 6.
  EXPECT_NEAR(CastRay(world, {2.0, 3.0}, kPi / 2.0, 8.0), 3.0, 1e-9);
}

TEST(SimRayCastTest, ReportsMaxRangeExactlyWithoutAHit) {
  const World world = MakeWalledRoom(30.0, 6.0, 0.1, kRes);
  EXPECT_EQ(CastRay(world, {1.0, 3.0}, 0.0, 8.0), 8.0);
  EXPECT_NEAR(CastRay(world, {25.0, 3.0}, 0.0, 8.0), 5.0, 1e-9);
}

TEST(SimRayCastTest, DoesNotSkipThinDiagonalWalls) {
  World world = MakeWalledRoom(20.0, 20.0, 0.1, kRes);
  // A chain of cells touching only at their corners, at 135 degrees, seen from (1, 1) between
  // about 6 and 84 degrees.
  FillSegment(world, {10.0, 2.0}, {2.0, 10.0}, 0.05, WorldCell::kOccupied);
  for (int i = 10; i <= 80; ++i) {
    const double angle = i * kPi / 180.0;
    EXPECT_LT(CastRay(world, {1.0, 1.0}, angle, 20.0), 12.0) << "beam at " << i << " deg went through";
  }
}

// The LMS-200 in a room whose wall is 2 m ahead of the sensor: the scan reads the geometry back.
TEST(SimLaserTest, ScanOfAWallTwoMetresAhead) {
  const World world = MakeWalledRoom(20.0, 20.0, 0.1, kRes);
  const Pose2D robot(17.84, 10.0, 0.0);  // sensor at x = 18.0, the wall at x = 20.0
  LaserOptions options;
  options.range_noise_stddev = 0.0;
  std::mt19937_64 rng(7);
  const LaserScan scan = SimulateScan(world, robot, options, rng);

  ASSERT_EQ(scan.ranges.size(), 181u);
  EXPECT_DOUBLE_EQ(scan.angle_min, -kPi / 2.0);
  EXPECT_DOUBLE_EQ(scan.angle_increment, kPi / 180.0);
  EXPECT_DOUBLE_EQ(scan.max_range, 8.0);
  EXPECT_DOUBLE_EQ(scan.sensor_offset.x, 0.16);
  EXPECT_NEAR(scan.ranges[90], 2.0, 1e-5);                               // straight ahead
  EXPECT_NEAR(scan.ranges[90 + 30], 2.0 / std::cos(kPi / 6.0), 1e-5);   // 30 deg left
  EXPECT_NEAR(scan.ranges[90 - 45], 2.0 / std::cos(kPi / 4.0), 1e-5);   // 45 deg right
  EXPECT_EQ(scan.ranges[0], 8.0f);  // to the right, the y = 0 wall is 10 m away: max range, exactly
  EXPECT_FALSE(scan.IsReturn(0));
  EXPECT_TRUE(scan.IsReturn(90));
}

TEST(SimLaserTest, RangeNoiseHasTheConfiguredSpread) {
  const World world = MakeWalledRoom(20.0, 20.0, 0.1, kRes);
  const Pose2D robot(17.84, 10.0, 0.0);
  LaserOptions options;  // default sigma = 1 cm
  std::mt19937_64 rng(11);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (int k = 0; k < 200; ++k) {
    const LaserScan scan = SimulateScan(world, robot, options, rng);
    const double e = scan.ranges[90] - 2.0;
    sum += e;
    sum2 += e * e;
    ++n;
  }
  const double mean = sum / n, stddev = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.003);
  EXPECT_NEAR(stddev, 0.01, 0.002);
}

}  // namespace
}  // namespace pslam
