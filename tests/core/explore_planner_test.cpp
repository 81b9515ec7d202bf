// A* on the inflated built map: around obstacles, cleanly failing when walled off, bounded.
#include <gtest/gtest.h>

#include <cmath>

#include "pslam/explore/path_planner.hpp"
#include "pslam/explore/planning_grid.hpp"
#include "pslam/grid/ray_caster.hpp"

namespace pslam {
namespace {

constexpr double kRes = 0.05;
constexpr int kFree = -2000;
constexpr int kOccupied = 3000;

int Cell(double metres) { return static_cast<int>(std::floor(metres / kRes)); }

// A fully known 6 m x 4 m room (cells 0..119 x 0..79 inside a one-cell wall).
OccupancyGrid Room() {
  OccupancyGrid grid(kRes);
  for (int y = -1; y <= 80; ++y) {
    for (int x = -1; x <= 120; ++x) {
      const bool wall = x < 0 || y < 0 || x >= 120 || y >= 80;
      grid.MutableAt(x, y) = static_cast<OccupancyGrid::Cell>(wall ? kOccupied : kFree);
    }
  }
  return grid;
}

// A wall across the room at x = 3 m from y = 0 up to 'top' metres.
void AddWall(OccupancyGrid& grid, double top) {
  for (int y = 0; y < Cell(top); ++y) {
    for (int x = Cell(3.0); x < Cell(3.1); ++x) grid.MutableAt(x, y) = kOccupied;
  }
}

// Every segment of the path crosses only traversable cells (the start cell excepted).
bool PathIsClear(const PlanningGrid& grid, const std::vector<Eigen::Vector2d>& path) {
  bool clear = true;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2i a = grid.WorldToCell(path[i - 1]), b = grid.WorldToCell(path[i]);
    TraceRay(a, b, [&](int x, int y) { clear = clear && (i == 1 || grid.IsTraversable({x, y})); });
    clear = clear && grid.IsTraversable(b);
  }
  return clear;
}

TEST(ExplorePlannerTest, InflationKeepsTheRobotRadiusAndMarginFromWalls) {
  const PlanningGrid grid(Room(), PlannerOptions{});
  // Clearance runs between cell centres: the wall's cells are centred at x = -0.025.
  EXPECT_NEAR(grid.Clearance({Cell(0.25), 40}), 0.30, 1e-6);
  EXPECT_FALSE(grid.IsTraversable({Cell(0.25), 40}));  // closer than 0.25 + 0.10
  EXPECT_TRUE(grid.IsTraversable({Cell(0.40), 40}));
  EXPECT_TRUE(grid.IsTraversable({60, 40}));
  EXPECT_NEAR(grid.Clearance({60, 40}), 2.0, 1e-6);  // the room's middle: 2 m from the top wall
  EXPECT_FALSE(grid.IsTraversable({500, 40}));   // outside the map: unknown
}

TEST(ExplorePlannerTest, FindsAPathAroundAnObstacle) {
  OccupancyGrid map = Room();
  AddWall(map, 2.8);  // leaves a 1.2 m gap at the top
  const PlanningGrid grid(map, PlannerOptions{});
  const Eigen::Vector2d start(1.0, 1.0), goal(5.0, 1.0);
  const PlannedPath path = PlanPath(grid, start, goal);
  ASSERT_EQ(path.status, PlanStatus::kFound);
  EXPECT_EQ(path.waypoints.front(), start);
  EXPECT_EQ(path.waypoints.back(), goal);
  // Up round the wall's end, about 0.35 m clear of it, and back down: about 5.9 m at best.
  EXPECT_GT(path.length, 5.8);
  EXPECT_LT(path.length, 7.5);
  EXPECT_TRUE(PathIsClear(grid, path.waypoints));
  EXPECT_LE(path.waypoints.size(), 8u);  // line-of-sight shortcuts leave a few corners
  bool over_the_wall = false;
  for (const auto& p : path.waypoints) over_the_wall = over_the_wall || p.y() > 2.8;
  EXPECT_TRUE(over_the_wall);
}

TEST(ExplorePlannerTest, StraightLineWhenNothingIsInTheWay) {
  const PlanningGrid grid(Room(), PlannerOptions{});
  const PlannedPath path = PlanPath(grid, {1.0, 2.0}, {5.0, 2.0});
  ASSERT_EQ(path.status, PlanStatus::kFound);
  EXPECT_EQ(path.waypoints.size(), 2u);
  EXPECT_NEAR(path.length, 4.0, 1e-9);
}

TEST(ExplorePlannerTest, FailsCleanlyWhenWalledOff) {
  OccupancyGrid map = Room();
  AddWall(map, 4.0);
  const PlanningGrid grid(map, PlannerOptions{});
  const PlannedPath path = PlanPath(grid, {1.0, 1.0}, {5.0, 1.0});
  EXPECT_EQ(path.status, PlanStatus::kNoPath);
  EXPECT_TRUE(path.waypoints.empty());
  EXPECT_GT(path.expanded_nodes, 0u);

  // A gap narrower than the robot plus margin is a wall too: 0.6 m < 2 x 0.35 m.
  OccupancyGrid narrow = Room();
  AddWall(narrow, 3.4);
  EXPECT_EQ(PlanPath(PlanningGrid(narrow, PlannerOptions{}), {1.0, 1.0}, {5.0, 1.0}).status, PlanStatus::kNoPath);
}

TEST(ExplorePlannerTest, ReportsBlockedGoalsStartsAndTheNodeLimit) {
  const OccupancyGrid map = Room();
  const PlanningGrid grid(map, PlannerOptions{});
  EXPECT_EQ(PlanPath(grid, {1.0, 1.0}, {0.1, 1.0}).status, PlanStatus::kGoalBlocked);   // too close to the wall
  EXPECT_EQ(PlanPath(grid, {1.0, 1.0}, {9.0, 1.0}).status, PlanStatus::kGoalBlocked);   // outside the map
  EXPECT_EQ(PlanPath(grid, {-3.0, 1.0}, {2.0, 1.0}).status, PlanStatus::kStartBlocked);  // far outside

  PlannerOptions capped;
  capped.max_expanded_nodes = 50;
  EXPECT_EQ(PlanPath(PlanningGrid(map, capped), {1.0, 1.0}, {5.0, 3.0}).status, PlanStatus::kNodeLimit);
}

TEST(ExplorePlannerTest, LeavesAStartInsideTheInflationBand) {
  const PlanningGrid grid(Room(), PlannerOptions{});
  const Eigen::Vector2d start(0.27, 2.0);  // the robot fits, but is closer than radius + margin
  ASSERT_FALSE(grid.IsTraversable(grid.WorldToCell(start)));
  const PlannedPath path = PlanPath(grid, start, {5.0, 2.0});
  ASSERT_EQ(path.status, PlanStatus::kFound);
  EXPECT_EQ(path.waypoints.front(), start);
  EXPECT_LT(path.length, 5.0);
}

TEST(ExplorePlannerTest, DijkstraTreeRanksEveryReachableCell) {
  OccupancyGrid map = Room();
  AddWall(map, 2.8);
  const PlanningGrid grid(map, PlannerOptions{});
  const SearchTree tree = GrowSearchTree(grid, {1.0, 1.0});
  EXPECT_FALSE(tree.truncated());
  EXPECT_TRUE(tree.Reached(grid.WorldToCell({5.0, 1.0})));
  EXPECT_GT(tree.Length(grid.WorldToCell({5.0, 1.0})), tree.Length(grid.WorldToCell({2.0, 3.0})));
  EXPECT_GE(tree.Cost(grid.WorldToCell({5.0, 1.0})), tree.Length(grid.WorldToCell({5.0, 1.0})));
  EXPECT_FALSE(tree.Reached(grid.WorldToCell({3.05, 1.0})));  // inside the wall
}

}  // namespace
}  // namespace pslam
