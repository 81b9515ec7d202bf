// The path follower driving the simulated robot, and the laser obstacle stop.
#include <gtest/gtest.h>

#include <numbers>

#include "pslam/explore/obstacle_stop.hpp"
#include "pslam/explore/path_follower.hpp"
#include "pslam/explore/path_planner.hpp"
#include "pslam/explore/planning_grid.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

Twist ToTwist(const DriveCommand& c) { return {c.linear, c.angular}; }

// An 8 m x 6 m room with a wall from the floor up to y = 4 m in the middle.
World RoomWithWall() {
  World world = MakeWalledRoom(8.0, 6.0, 0.1, 0.05);
  FillBox(world, {3.8, 0.0}, {4.0, 4.0}, WorldCell::kOccupied);
  return world;
}

TEST(ExploreFollowerTest, ReachesAGoalAroundAWallInTheSimulator) {
  const World world = RoomWithWall();
  Simulator sim(world, Pose2D(1.5, 1.5, -std::numbers::pi / 2.0));  // facing away from the path
  const PlanningGrid grid(world.ToGrid(), PlannerOptions{});
  const Eigen::Vector2d goal(6.5, 1.5);
  const PlannedPath path = PlanPath(grid, sim.true_pose().translation(), goal);
  ASSERT_EQ(path.status, PlanStatus::kFound);

  PathFollower follower;
  follower.SetPath(path.waypoints);
  bool reached = false;
  double max_speed = 0.0;
  while (sim.time() < 150.0 && !reached) {
    const FollowerOutput out = follower.Update(sim.true_pose());
    reached = out.goal_reached;
    max_speed = std::max(max_speed, out.command.linear);
    sim.SetCommand(ToTwist(out.command));
    ASSERT_FALSE(sim.Step(0.1).collided) << "at t = " << sim.time();
  }
  ASSERT_TRUE(reached);
  EXPECT_LT((sim.true_pose().translation() - goal).norm(), 0.2);
  EXPECT_LT(sim.time(), path.length / 0.2 * 1.6 + 5.0);  // near top speed most of the way
  EXPECT_NEAR(max_speed, 0.2, 1e-3);  // straight stretches at (almost exactly) top speed
  // Stopped at the goal: no further command.
  EXPECT_EQ(follower.Update(sim.true_pose()).command.linear, 0.0);
}

TEST(ExploreFollowerTest, TurnsInPlaceWhenThePathIsBehind) {
  PathFollower follower;
  follower.SetPath({{0.0, 0.0}, {-2.0, 0.0}});
  const FollowerOutput out = follower.Update(Pose2D(0.0, 0.0, 0.0));
  EXPECT_FALSE(out.goal_reached);
  EXPECT_EQ(out.command.linear, 0.0);
  EXPECT_NE(out.command.angular, 0.0);
}

TEST(ExploreFollowerTest, SlowsForTurns) {
  PathFollower follower;
  follower.SetPath({{0.0, 0.0}, {3.0, 0.0}});
  const double straight = follower.Update(Pose2D(0.0, 0.0, 0.0)).command.linear;
  const double skewed = follower.Update(Pose2D(0.0, 0.0, 0.5)).command.linear;
  EXPECT_NEAR(straight, 0.2, 1e-9);
  EXPECT_GT(skewed, 0.0);
  EXPECT_LT(skewed, 0.5 * straight);
}

// A scan with every beam at 'far' except beam 'index' at 'range'.
LaserScan ScanWith(int index, float range, float far = 5.0f) {
  LaserScan scan;
  scan.angle_min = -std::numbers::pi / 2.0;
  scan.angle_increment = std::numbers::pi / 180.0;
  scan.max_range = 8.0;
  scan.ranges.assign(181, far);
  scan.ranges[static_cast<std::size_t>(index)] = range;
  return scan;
}

TEST(ExploreObstacleStopTest, StopsForwardMotionForCloseReturnsAhead) {
  EXPECT_TRUE(ObstacleAhead(ScanWith(90 + 20, 0.3f)));   // 20 deg left, 0.30 m
  EXPECT_TRUE(ObstacleAhead(ScanWith(90 - 30, 0.3f)));   // 30 deg right: on the edge
  EXPECT_FALSE(ObstacleAhead(ScanWith(90 + 40, 0.3f)));  // 40 deg: beside, not ahead
  EXPECT_FALSE(ObstacleAhead(ScanWith(90, 0.4f)));       // ahead but far enough
  EXPECT_FALSE(ObstacleAhead(ScanWith(90, 0.0f)));       // invalid reading, not an obstacle

  const LaserScan blocked = ScanWith(90, 0.2f);
  const DriveCommand forward = ApplyObstacleStop({0.2, 0.3}, blocked);
  EXPECT_EQ(forward.linear, 0.0);
  EXPECT_EQ(forward.angular, 0.3);  // may still turn away
  EXPECT_EQ(ApplyObstacleStop({-0.1, 0.0}, blocked).linear, -0.1);  // and back off
  EXPECT_EQ(ApplyObstacleStop({0.2, 0.0}, ScanWith(90, 2.0f)).linear, 0.2);
}

TEST(ExploreObstacleStopTest, StopsTheSimulatedRobotBeforeAWall) {
  Simulator sim(MakeWalledRoom(10.0, 4.0, 0.1, 0.05), Pose2D(7.0, 2.0, 0.0));
  LaserScan last;
  for (int i = 0; i < 300; ++i) {
    const StepResult r = sim.Step(0.1);
    ASSERT_FALSE(r.collided);
    for (const auto& e : r.events) {
      if (const auto* scan = std::get_if<LaserScan>(&e.data)) last = *scan;
    }
    sim.SetCommand(ToTwist(ApplyObstacleStop({0.2, 0.0}, last)));
  }
  const double sensor_to_wall = 10.0 - (sim.true_pose().x + 0.16);
  EXPECT_LT(sensor_to_wall, 0.35);  // triggered ...
  EXPECT_GT(sensor_to_wall, 0.15);  // ... with room to brake: the bumper is 9 cm ahead of the sensor
  EXPECT_EQ(sim.velocity().linear, 0.0);
  EXPECT_EQ(sim.collision_count(), 0u);
}

}  // namespace
}  // namespace pslam
