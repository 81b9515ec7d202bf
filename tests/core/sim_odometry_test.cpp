// Odometry drift: grows with the distance driven, stays put when the robot does, and is the same
// for the same seed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <variant>
#include <vector>

#include "pslam/sim/odometry_model.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

// Position error of odometry after driving 'meters' straight ahead in 1 cm increments.
double ErrorAfter(double meters, std::uint64_t seed) {
  DriftingOdometry odometry(Pose2D(0, 0, 0), OdometryNoiseOptions{}, seed);
  const int steps = static_cast<int>(std::lround(meters / 0.01));
  for (int i = 0; i < steps; ++i) odometry.Advance(Pose2D(0.01, 0.0, 0.0));
  return std::hypot(odometry.pose().x - meters, odometry.pose().y);
}

TEST(SimOdometryTest, DriftGrowsWithDistance) {
  double short_run = 0.0, long_run = 0.0;
  constexpr int kSeeds = 40;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    short_run += ErrorAfter(2.0, seed) / kSeeds;
    long_run += ErrorAfter(20.0, seed) / kSeeds;
  }
  EXPECT_GT(short_run, 0.005);           // real wheels are never exact ...
  EXPECT_GT(long_run, 4.0 * short_run);  // ... and 10x the distance gives several times the error
  EXPECT_LT(long_run, 2.0);              // but it stays odometry, not noise
}

TEST(SimOdometryTest, StandingStillDoesNotDrift) {
  DriftingOdometry odometry(Pose2D(1, 2, 0.5), OdometryNoiseOptions{}, 3);
  for (int i = 0; i < 100; ++i) odometry.Advance(Pose2D());
  EXPECT_EQ(odometry.pose().x, 1.0);
  EXPECT_EQ(odometry.pose().y, 2.0);
  EXPECT_EQ(odometry.pose().theta, 0.5);
}

TEST(SimOdometryTest, TurningInPlaceDriftsInHeadingOnly) {
  DriftingOdometry odometry(Pose2D(0, 0, 0), OdometryNoiseOptions{}, 5);
  for (int i = 0; i < 628; ++i) odometry.Advance(Pose2D(0.0, 0.0, 0.01));  // one full turn
  EXPECT_EQ(odometry.pose().x, 0.0);
  EXPECT_EQ(odometry.pose().y, 0.0);
  EXPECT_GT(std::abs(NormalizeAngle(odometry.pose().theta - 6.28)), 1e-4);
}

// Drives the simulator through a square and returns its odometry trajectory.
std::vector<Pose2D> OdometryTrack(std::uint64_t seed) {
  SimulatorOptions options;
  options.seed = seed;
  Simulator sim(MakeWalledRoom(10.0, 10.0, 0.1, 0.05), Pose2D(2.0, 2.0, 0.0), options);
  std::vector<Pose2D> track;
  for (int side = 0; side < 4; ++side) {
    sim.SetCommand({0.2, 0.0});
    for (const auto& e : sim.Step(25.0).events) {
      if (const auto* o = std::get_if<OdometryReading>(&e.data)) track.push_back(o->pose);
    }
    sim.SetCommand({0.0, 0.0});
    sim.Step(1.0);
    sim.SetCommand({0.0, std::numbers::pi / 2.0 / 2.0});
    sim.Step(2.0);
  }
  return track;
}

TEST(SimOdometryTest, DeterministicForASeed) {
  const auto a = OdometryTrack(42), b = OdometryTrack(42), c = OdometryTrack(43);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
    EXPECT_EQ(a[i].theta, b[i].theta);
  }
  EXPECT_NE(a.back().x, c.back().x);
}

}  // namespace
}  // namespace pslam
