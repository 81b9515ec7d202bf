// Route order and planning cost of target selection: what a frontier is worth, keeping the current
// goal, a search bounded by the best goal found, and the way into space a prediction sealed off.
#include <gtest/gtest.h>

#include "pslam/explore/explorer.hpp"

namespace pslam {
namespace {

constexpr int kFree = -2000;
constexpr int kOccupied = 3000;
constexpr double kRes = 0.05;

int Cell(double metres) { return static_cast<int>(std::lround(metres / kRes)); }

// Sets the cells of [x0, x1) x [y0, y1) (metres).
void Fill(OccupancyGrid& grid, double x0, double y0, double x1, double y1, int value) {
  for (int y = Cell(y0); y < Cell(y1); ++y) {
    for (int x = Cell(x0); x < Cell(x1); ++x) grid.MutableAt(x, y) = static_cast<OccupancyGrid::Cell>(value);
  }
}

// A known corridor [0, length] x [0, 2] m with walls along both sides; its ends are open to unknown
// space unless closed.
OccupancyGrid Corridor(double length, bool left_open, bool right_open) {
  OccupancyGrid grid(kRes);
  Fill(grid, 0.0, 0.0, length, 2.0, kFree);
  Fill(grid, -0.05, -0.05, length + 0.05, 0.0, kOccupied);
  Fill(grid, -0.05, 2.0, length + 0.05, 2.05, kOccupied);
  if (!left_open) Fill(grid, -0.05, 0.0, 0.0, 2.0, kOccupied);
  if (!right_open) Fill(grid, length, 0.0, length + 0.05, 2.0, kOccupied);
  return grid;
}

ExploreRequest RobotAt(double x, double y) {
  ExploreRequest request;
  request.robot_position = {x, y};
  return request;
}

TEST(ExploreRouteTest, KeepsTheCurrentGoalUnlessAnotherIsClearlyNearer) {
  // Both ends open; from x = 19 m the left end is 2 m nearer than the right one.
  const OccupancyGrid grid = Corridor(40.0, true, true);
  ExploreRequest request = RobotAt(19.0, 1.0);
  EXPECT_LT(SelectNextTarget(grid, request).target->position.x(), 1.0);

  // Driving to the right end already: 2 m is not enough to turn back.
  request.current_goal = Eigen::Vector2d(39.9, 1.0);
  EXPECT_GT(SelectNextTarget(grid, request).target->position.x(), 39.0);

  // From x = 14 m the left end is 12 m nearer: turn.
  request.robot_position = {14.0, 1.0};
  EXPECT_LT(SelectNextTarget(grid, request).target->position.x(), 1.0);
}

TEST(ExploreRouteTest, AWideOpeningBeatsASlightlyNearerPocket) {
  // A corridor closed on the left and open on the right (2 m of frontier), with a 10 cm square
  // never seen on its floor at x = 10.9 m, as beside a desk: a pocket of 0.4 m of frontier.
  OccupancyGrid grid = Corridor(12.0, false, true);
  Fill(grid, 10.9, 1.0, 11.0, 1.1, OccupancyGrid::kUnknown);
  // From x = 8.5 m the pocket is about 2.35 m away, the open end about 3.45 m.
  const ExploreDecision decision = SelectNextTarget(grid, RobotAt(8.5, 1.0));
  ASSERT_FALSE(decision.done());
  EXPECT_EQ(decision.clusters, 2);
  EXPECT_GT(decision.target->position.x(), 11.9);

  // Worth nothing, the nearest wins, as before.
  ExploreOptions nearest;
  nearest.gain_weight = 0.0;
  EXPECT_NEAR(SelectNextTarget(grid, RobotAt(8.5, 1.0), nearest).target->position.x(), 10.95, 0.15);
}

TEST(ExploreRouteTest, TheSearchStopsOnceTheBestGoalIsSettled) {
  // A 40 m x 30 m known room, walled, with a 1 m opening in its left wall next to the robot.
  OccupancyGrid grid(kRes);
  Fill(grid, 0.0, 0.0, 40.0, 30.0, kFree);
  Fill(grid, -0.05, -0.05, 40.05, 0.0, kOccupied);
  Fill(grid, -0.05, 30.0, 40.05, 30.05, kOccupied);
  Fill(grid, -0.05, 0.0, 0.0, 30.0, kOccupied);
  Fill(grid, 40.0, 0.0, 40.05, 30.0, kOccupied);
  Fill(grid, -0.05, 14.5, 0.0, 15.5, OccupancyGrid::kUnknown);
  const ExploreDecision decision = SelectNextTarget(grid, RobotAt(2.0, 15.0));
  ASSERT_FALSE(decision.done());
  EXPECT_LT(decision.target->position.x(), 0.1);
  EXPECT_FALSE(decision.search_truncated);
  // The room holds about 450 000 traversable cells; the goal is 2 m away, and nothing more than the
  // goal's cost plus the most a cluster can be worth (5 m) needs to be searched.
  EXPECT_GT(decision.expanded_nodes, 0u);
  EXPECT_LT(decision.expanded_nodes, 40000u);
}

// A corridor whose side walls are mapped on to x = 12 m; beyond x = 10 m a hypothesis predicts 2 m
// more corridor and a wall across it at x = 12 m, merged into the map. In truth the corridor opens
// there onto a hall, part of which the laser saw through a gap: known free space at x in [13, 16] m,
// y in [-3, 5] m, with unknown space west and east of it. Closed at x = 0, or open at x = -30 m.
OccupancyGrid CorridorSealedByAPrediction(bool left_open) {
  OccupancyGrid grid = Corridor(10.0, false, true);
  if (left_open) {
    Fill(grid, -30.0, 0.0, 0.05, 2.0, kFree);
    Fill(grid, -30.0, -0.05, 0.0, 0.0, kOccupied);
    Fill(grid, -30.0, 2.0, 0.0, 2.05, kOccupied);
  }
  Fill(grid, 10.0, 0.0, 12.0, 2.0, kFree);
  Fill(grid, 12.0, 0.0, 12.05, 2.0, kOccupied);
  Fill(grid, 10.0, -0.05, 12.05, 0.0, kOccupied);  // mapped
  Fill(grid, 10.0, 2.0, 12.05, 2.05, kOccupied);
  Fill(grid, 13.0, -3.0, 16.0, 5.0, kFree);
  Fill(grid, 13.0, -3.05, 16.0, -3.0, kOccupied);
  Fill(grid, 13.0, 5.0, 16.0, 5.05, kOccupied);
  return grid;
}

ExploreOptions WithWayIns() {
  ExploreOptions options;
  options.mode = ExploreMode::kSkipPredicted;
  options.way_in_cost_factor = 3.0;
  return options;
}

// The robot at (x, 1) in CorridorSealedByAPrediction, told what the hypothesis predicts.
ExploreRequest InTheSealedCorridorAt(double x) {
  ExploreRequest request = RobotAt(x, 1.0);
  request.covered = [](const Eigen::Vector2i& c) {  // between the mapped side walls
    return c.x() >= Cell(10.0) && c.x() <= Cell(12.0) && c.y() >= 0 && c.y() < Cell(2.0);
  };
  request.predicted = request.covered;
  request.predicted_wall = [](const Eigen::Vector2i& c) { return c.x() == Cell(12.0); };
  return request;
}

TEST(ExploreRouteTest, APredictedWallDoesNotSealAWingOff) {
  const OccupancyGrid grid = CorridorSealedByAPrediction(false);
  ExploreOptions options = WithWayIns();
  ExploreRequest request = InTheSealedCorridorAt(2.0);

  const ExploreDecision decision = SelectNextTarget(grid, request, options);
  ASSERT_FALSE(decision.done());
  EXPECT_EQ(decision.unreachable,
            decision.clusters);  // no frontier a traversable way reaches
  EXPECT_TRUE(decision.target->way_in);
  // The target is where the way to the hall leaves the traversable space: the predicted corridor's
  // end.
  EXPECT_GT(decision.target->position.x(), 11.0);
  EXPECT_LT(decision.target->position.x(), 12.0);
  EXPECT_GT(decision.target->path.size(), 1u);

  // Once that exit has been reached, and the wall really is there, it is not offered again.
  request.tried_way_ins = {decision.target->position};
  EXPECT_TRUE(SelectNextTarget(grid, request, options).done());

  // Without the way in, the run would end here with the hall unexplored.
  request.tried_way_ins.clear();
  options.way_in_cost_factor = 0.0;
  EXPECT_TRUE(SelectNextTarget(grid, request, options).done());
}

TEST(ExploreRouteTest, AWayInIsTakenWhenFarNearerThanTheFrontierOtherwiseChosen) {
  // The corridor goes on left to x = -30 m, where it is open: a frontier a traversable way reaches.
  const OccupancyGrid grid = CorridorSealedByAPrediction(true);
  // At x = 9 m the way in (3 m to the predicted wall, then about 1 m of unverified cells at three
  // times their length) costs far less than the 39 m to the left end: look behind the wall in
  // passing, rather than come back once the rest is done.
  ExploreDecision decision = SelectNextTarget(grid, InTheSealedCorridorAt(9.0), WithWayIns());
  ASSERT_FALSE(decision.done());
  EXPECT_TRUE(decision.target->way_in);
  EXPECT_GT(decision.target->position.x(), 11.0);

  // At x = -20 m the left end is the nearer; at x = 0, 30 m from it, the way in is nearer, but not
  // three times: no detour for a guess.
  for (const double x : {-20.0, 0.0}) {
    decision = SelectNextTarget(grid, InTheSealedCorridorAt(x), WithWayIns());
    ASSERT_FALSE(decision.done());
    EXPECT_FALSE(decision.target->way_in) << x;
    EXPECT_LT(decision.target->position.x(), -29.9) << x;
  }
}

}  // namespace
}  // namespace pslam
