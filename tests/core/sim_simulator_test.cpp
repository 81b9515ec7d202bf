// The simulated clock: event rates, timestamps and the fields of emitted scans.
#include <gtest/gtest.h>

#include <chrono>
#include <variant>

#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

struct Counts {
  int scans = 0;
  int odometry = 0;
};

Counts Count(const StepResult& result) {
  Counts c;
  for (const auto& e : result.events) (std::holds_alternative<LaserScan>(e.data) ? c.scans : c.odometry)++;
  return c;
}

World Room() { return MakeWalledRoom(10.0, 10.0, 0.1, 0.05); }

TEST(SimSimulatorTest, EmitsScansAtFiveHertzAndOdometryAtTen) {
  SimulatorOptions options;
  options.start_time_seconds = 1000.0;
  Simulator sim(Room(), Pose2D(5, 5, 0), options);
  const Counts first = Count(sim.Step(1.0));  // t = 1000 .. 1001 inclusive
  EXPECT_EQ(first.scans, 6);
  EXPECT_EQ(first.odometry, 11);
  // Many small steps: no event is lost or doubled by rounding.
  Counts rest;
  for (int i = 0; i < 100; ++i) {
    const Counts c = Count(sim.Step(0.1));
    rest.scans += c.scans;
    rest.odometry += c.odometry;
  }
  EXPECT_EQ(rest.scans, 50);
  EXPECT_EQ(rest.odometry, 100);
  EXPECT_NEAR(sim.time(), 1011.0, 1e-9);
}

TEST(SimSimulatorTest, EventsAreOrderedAndScansCarryTheirOdometry) {
  SimulatorOptions options;
  options.start_time_seconds = 1234.5;
  Simulator sim(Room(), Pose2D(5, 5, 0), options);
  sim.SetCommand({0.2, 0.3});
  const StepResult result = sim.Step(2.0);
  double last_time = -1.0;
  const OdometryReading* last_odometry = nullptr;
  int scans = 0;
  for (const auto& e : result.events) {
    if (const auto* o = std::get_if<OdometryReading>(&e.data)) {
      EXPECT_GE(o->timestamp, last_time);
      last_time = o->timestamp;
      last_odometry = o;
      continue;
    }
    const auto& scan = std::get<LaserScan>(e.data);
    ++scans;
    EXPECT_EQ(e.time, scan.timestamp);
    EXPECT_GE(scan.timestamp, last_time);
    last_time = scan.timestamp;
    // Scans fall on odometry instants (5 Hz divides 10 Hz), and the reading comes first.
    ASSERT_NE(last_odometry, nullptr);
    EXPECT_EQ(last_odometry->timestamp, scan.timestamp);
    EXPECT_EQ(scan.odometry.x, last_odometry->pose.x);
    EXPECT_EQ(scan.odometry.theta, last_odometry->pose.theta);
    EXPECT_EQ(scan.ranges.size(), 181u);
    EXPECT_EQ(scan.max_range, 8.0);
    EXPECT_DOUBLE_EQ(scan.sensor_offset.x, 0.16);
  }
  EXPECT_EQ(scans, 11);
  // The step ends on an event instant, whose ground truth is the robot's pose now.
  EXPECT_EQ(result.events.back().true_pose.x, sim.true_pose().x);
  EXPECT_EQ(result.events.back().true_pose.y, sim.true_pose().y);
  EXPECT_NE(result.events.front().true_pose.x, sim.true_pose().x);
  for (const auto& e : result.events) {
    if (const auto* scan = std::get_if<LaserScan>(&e.data); scan && scan->timestamp > 1234.6) {
      EXPECT_EQ(scan->timestamp_text, "1234.700000");
      break;
    }
  }
}

TEST(SimSimulatorTest, RunsFarFasterThanRealTime) {
  Simulator sim(Room(), Pose2D(5, 5, 0));
  sim.SetCommand({0.0, 0.5});
  const auto start = std::chrono::steady_clock::now();
  std::size_t scans = 0;
  for (int i = 0; i < 600; ++i) scans += static_cast<std::size_t>(Count(sim.Step(1.0)).scans);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(scans, 3001u);
  EXPECT_LT(wall, 3.0);  // ten minutes of simulated time
}

}  // namespace
}  // namespace pslam
