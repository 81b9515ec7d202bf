// Target selection: nearest reachable frontier cluster, skip-predicted mode, blacklist, done.
#include <gtest/gtest.h>

#include "pslam/explore/explorer.hpp"

namespace pslam {
namespace {

constexpr int kFree = -2000;
constexpr int kOccupied = 3000;

// A known 6 m x 4 m room with two 1 m openings into unknown space: one in the left wall (x = 0)
// and one in the right wall (x = 6), both between y = 1.5 m and 2.5 m.
OccupancyGrid RoomWithTwoOpenings() {
  OccupancyGrid grid(0.05);
  for (int y = -1; y <= 80; ++y) {
    for (int x = -1; x <= 120; ++x) {
      const bool wall = x < 0 || y < 0 || x >= 120 || y >= 80;
      const bool opening = (x < 0 || x >= 120) && y >= 30 && y < 50;
      if (!opening) grid.MutableAt(x, y) = static_cast<OccupancyGrid::Cell>(wall ? kOccupied : kFree);
    }
  }
  return grid;
}

ExploreRequest RobotAt(double x, double y) {
  ExploreRequest request;
  request.robot_position = {x, y};
  return request;
}

TEST(ExploreExplorerTest, FullCoverageGoesToTheNearestCluster) {
  const OccupancyGrid grid = RoomWithTwoOpenings();
  const ExploreDecision decision = SelectNextTarget(grid, RobotAt(1.5, 2.0));
  ASSERT_FALSE(decision.done());
  EXPECT_EQ(decision.clusters, 2);
  EXPECT_NEAR(decision.target->position.x(), 0.025, 1e-9);  // the left opening
  EXPECT_NEAR(decision.target->position.y(), 2.0, 0.05);
  EXPECT_NEAR(decision.target->path_length, 1.475, 0.05);
  ASSERT_GE(decision.target->path.size(), 2u);
  EXPECT_EQ(decision.target->path.front(), Eigen::Vector2d(1.5, 2.0));
  EXPECT_EQ(decision.target->path.back(), decision.target->position);

  // From the right half of the room the right opening is nearer.
  EXPECT_GT(SelectNextTarget(grid, RobotAt(4.5, 2.0)).target->position.x(), 5.9);
}

TEST(ExploreExplorerTest, SkipPredictedSkipsAFullyCoveredCluster) {
  const OccupancyGrid grid = RoomWithTwoOpenings();
  ExploreOptions options;
  options.mode = ExploreMode::kSkipPredicted;
  ExploreRequest request = RobotAt(1.5, 2.0);
  request.covered = [](const Eigen::Vector2i& c) { return c.x() < 0; };  // a hypothesis fills the left
  const ExploreDecision decision = SelectNextTarget(grid, request, options);
  ASSERT_FALSE(decision.done());
  EXPECT_EQ(decision.skipped, 1);
  EXPECT_GT(decision.target->position.x(), 5.9);  // the right opening, though farther

  // Full coverage ignores the predicate.
  options.mode = ExploreMode::kFullCoverage;
  EXPECT_LT(SelectNextTarget(grid, request, options).target->position.x(), 0.1);

  // Everything covered: nothing left to explore.
  options.mode = ExploreMode::kSkipPredicted;
  request.covered = [](const Eigen::Vector2i&) { return true; };
  const ExploreDecision all = SelectNextTarget(grid, request, options);
  EXPECT_TRUE(all.done());
  EXPECT_EQ(all.skipped, 2);
}

TEST(ExploreExplorerTest, PredictedWallsStopTheCoveredFlood) {
  // Left of the left opening a hypothesis covers a 0.5 m band (x in [-10, -1] cells) and predicts
  // its far column as a wall. Behind that wall lies unknown space nothing predicts, such as an
  // obstacle's interior; the robot would not reveal it by going to this frontier.
  const OccupancyGrid grid = RoomWithTwoOpenings();
  const CoveredPredicate covered = [](const Eigen::Vector2i& c) { return c.x() >= -10 && c.x() < 0; };
  const CoveredPredicate wall = [](const Eigen::Vector2i& c) { return c.x() == -10; };
  const FrontierCluster* left = nullptr;
  const std::vector<FrontierCluster> clusters = FindFrontierClusters(grid, FrontierOptions{});
  for (const FrontierCluster& c : clusters) {
    if (c.centroid.x() < 1.0) left = &c;
  }
  ASSERT_NE(left, nullptr);
  ExploreRequest predictions;
  predictions.covered = covered;
  const auto flooded = CoveredFraction(grid, *left, predictions, 2.0);
  predictions.predicted_wall = wall;
  const auto walled = CoveredFraction(grid, *left, predictions, 2.0);
  ASSERT_TRUE(flooded && walled);
  EXPECT_LT(*flooded, 0.5);  // the flood runs on behind the wall
  EXPECT_GT(*walled, 0.9);   // only the corner around the room's outside is left uncovered

  // So the explorer skips the left opening with the walls, and goes there without them.
  ExploreOptions options;
  options.mode = ExploreMode::kSkipPredicted;
  ExploreRequest request = RobotAt(1.5, 2.0);
  request.covered = covered;
  EXPECT_LT(SelectNextTarget(grid, request, options).target->position.x(), 0.1);
  request.predicted_wall = wall;
  const ExploreDecision decision = SelectNextTarget(grid, request, options);
  EXPECT_EQ(decision.skipped, 1);
  EXPECT_GT(decision.target->position.x(), 5.9);
}

TEST(ExploreExplorerTest, NarrowGapsInAWallDoNotLetTheCoveredFloodThrough) {
  // As above, but the predicted wall has a 2-cell gap (10 cm), as walls seen at a grazing angle
  // do. The unknown space behind the gap is no more the frontier's than behind the rest.
  const OccupancyGrid grid = RoomWithTwoOpenings();
  const CoveredPredicate covered = [](const Eigen::Vector2i& c) { return c.x() >= -10 && c.x() < 0; };
  const CoveredPredicate gappy_wall = [](const Eigen::Vector2i& c) {
    return c.x() == -10 && c.y() != 39 && c.y() != 40;
  };
  const std::vector<FrontierCluster> clusters = FindFrontierClusters(grid, FrontierOptions{});
  ASSERT_EQ(clusters.size(), 2u);
  const FrontierCluster& left = clusters[0].centroid.x() < 3.0 ? clusters[0] : clusters[1];
  ExploreRequest predictions;
  predictions.covered = covered;
  predictions.predicted_wall = gappy_wall;
  const auto leaking = CoveredFraction(grid, left, predictions, 2.0, 0);
  const auto sealed = CoveredFraction(grid, left, predictions, 2.0, 2);
  ASSERT_TRUE(leaking && sealed);
  EXPECT_LT(*leaking, 0.8);  // through the gap the flood reaches 1.5 m of unpredicted space
  EXPECT_GT(*sealed, 0.9);

  // The explorer seals gaps by default, so it skips the left opening.
  ExploreOptions options;
  options.mode = ExploreMode::kSkipPredicted;
  ExploreRequest request = RobotAt(1.5, 2.0);
  request.covered = covered;
  request.predicted_wall = gappy_wall;
  EXPECT_EQ(SelectNextTarget(grid, request, options).skipped, 1);
  options.wall_seal_cells = 0;
  EXPECT_EQ(SelectNextTarget(grid, request, options).skipped, 0);
}

TEST(ExploreExplorerTest, PartlyCoveredClustersAreStillExplored) {
  const OccupancyGrid grid = RoomWithTwoOpenings();
  const auto clusters = FindFrontierClusters(grid);
  ASSERT_EQ(clusters.size(), 2u);
  const FrontierCluster& left = clusters[0].centroid.x() < 3.0 ? clusters[0] : clusters[1];
  // Cover only the unknown cells more than 1 m beyond the opening: about half of the 2 m reach.
  const CoveredPredicate far = [](const Eigen::Vector2i& c) { return c.x() < -20; };
  ExploreRequest predictions;
  predictions.covered = far;
  const auto fraction = CoveredFraction(grid, left, predictions, 2.0);
  ASSERT_TRUE(fraction.has_value());
  EXPECT_GT(*fraction, 0.2);
  EXPECT_LT(*fraction, 0.8);

  ExploreOptions options;
  options.mode = ExploreMode::kSkipPredicted;
  ExploreRequest request = RobotAt(1.5, 2.0);
  request.covered = far;
  const ExploreDecision decision = SelectNextTarget(grid, request, options);
  EXPECT_EQ(decision.skipped, 0);
  EXPECT_LT(decision.target->position.x(), 0.1);
}

TEST(ExploreExplorerTest, UndecidedCellsCountOnlyWhereAHypothesisPredictsThem) {
  // The first metre beyond the left opening was observed but is undecided (p = 0.5); hypotheses
  // predict all the rest.
  OccupancyGrid grid = RoomWithTwoOpenings();
  for (int y = -60; y <= 140; ++y) {
    for (int x = -20; x < 0; ++x) {
      if (!grid.IsKnown(x, y)) grid.MutableAt(x, y) = 0;
    }
  }
  const auto clusters = FindFrontierClusters(grid);
  ASSERT_EQ(clusters.size(), 2u);
  const FrontierCluster& left = clusters[0].centroid.x() < 3.0 ? clusters[0] : clusters[1];
  ExploreRequest request;
  request.covered = [](const Eigen::Vector2i& c) { return c.x() < -20 || c.x() >= 0; };
  const auto fraction = CoveredFraction(grid, left, request, 2.0);
  ASSERT_TRUE(fraction.has_value());
  EXPECT_DOUBLE_EQ(*fraction, 1.0);

  // Nothing predicted: the undecided metre does not make the frontier look covered.
  request.covered = {};
  EXPECT_EQ(CoveredFraction(grid, left, request, 2.0), std::optional<double>(0.0));
  // Only undecided cells within reach: nothing to judge by.
  EXPECT_EQ(CoveredFraction(grid, left, request, 0.9), std::nullopt);

  // A hypothesis predicts the undecided metre too (P-SLAM covers the cells of S_f it has not
  // decided, not only those it never observed): they count as covered ...
  request.covered = [](const Eigen::Vector2i& c) { return c.x() < 0; };
  request.predicted = request.covered;
  EXPECT_EQ(CoveredFraction(grid, left, request, 0.9), std::optional<double>(1.0));
  // ... and with the space behind them not predicted, the frontier is mostly uncovered.
  request.covered = [](const Eigen::Vector2i& c) { return c.x() >= -20 && c.x() < 0; };
  request.predicted = request.covered;
  const auto partly = CoveredFraction(grid, left, request, 2.0);
  ASSERT_TRUE(partly.has_value());
  EXPECT_GT(*partly, 0.0);
  EXPECT_LT(*partly, 0.8);
}

TEST(ExploreExplorerTest, OnTheMergedMapAnUnknownGapBetweenPredictionsIsSkipped) {
  // The merged map: beyond the left opening a hypothesis predicts 2 m of free space, which the
  // merged map shows as free, all but a 30 cm x 30 cm gap it left unknown. The gap's rim is a
  // frontier nearer than the right opening.
  OccupancyGrid merged = RoomWithTwoOpenings();
  const auto in_gap = [](const Eigen::Vector2i& c) { return c.x() >= -25 && c.x() < -19 && c.y() >= 37 && c.y() < 43; };
  const auto in_prediction = [&](const Eigen::Vector2i& c) { return c.x() >= -40 && c.x() < 0 && !in_gap(c); };
  for (int y = -1; y <= 80; ++y) {
    for (int x = -41; x < 0; ++x) {
      const Eigen::Vector2i c(x, y);
      const bool wall = x == -41 || y < 0 || y >= 80;
      if (wall) merged.MutableAt(x, y) = kOccupied;
      if (!wall && in_prediction(c)) merged.MutableAt(x, y) = kFree;
    }
  }
  ExploreOptions options;
  options.mode = ExploreMode::kSkipPredicted;
  ExploreRequest request = RobotAt(1.5, 2.0);
  request.covered = in_prediction;
  // Asked only about the merged map's unknown cells, the gap's frontier looks wholly unpredicted.
  const ExploreDecision unaware = SelectNextTarget(merged, request, options);
  ASSERT_FALSE(unaware.done());
  EXPECT_EQ(unaware.skipped, 0);
  EXPECT_LT(unaware.target->position.x(), -0.9);
  // Its unexplored surroundings are the predicted cells around it: skipped.
  request.predicted = in_prediction;
  const ExploreDecision aware = SelectNextTarget(merged, request, options);
  ASSERT_FALSE(aware.done());
  EXPECT_EQ(aware.skipped, 1);
  EXPECT_GT(aware.target->position.x(), 5.9);
}

TEST(ExploreExplorerTest, BlacklistedTargetsAreLeftOut) {
  const OccupancyGrid grid = RoomWithTwoOpenings();
  ExploreRequest request = RobotAt(1.5, 2.0);
  request.blacklist.push_back({0.0, 2.0});
  const ExploreDecision decision = SelectNextTarget(grid, request);
  EXPECT_EQ(decision.blacklisted, 1);
  EXPECT_GT(decision.target->position.x(), 5.9);
}

TEST(ExploreExplorerTest, FrontiersOutsideTheAreaAreNotTargets) {
  const OccupancyGrid grid = RoomWithTwoOpenings();
  ExploreOptions options;
  options.area = Eigen::AlignedBox2d(Eigen::Vector2d(0.5, -0.1), Eigen::Vector2d(6.5, 4.1));  // not the left opening
  const ExploreDecision decision = SelectNextTarget(grid, RobotAt(1.5, 2.0), options);
  ASSERT_FALSE(decision.done());
  EXPECT_EQ(decision.outside_area, 1);
  EXPECT_GT(decision.target->position.x(), 5.9);

  // Neither opening inside: exploring is done.
  options.area = Eigen::AlignedBox2d(Eigen::Vector2d(0.5, -0.1), Eigen::Vector2d(5.5, 4.1));
  const ExploreDecision none = SelectNextTarget(grid, RobotAt(1.5, 2.0), options);
  EXPECT_TRUE(none.done());
  EXPECT_EQ(none.outside_area, 2);
}

TEST(ExploreExplorerTest, DoneWhenNoFrontierOrNoneReachable) {
  OccupancyGrid closed = RoomWithTwoOpenings();
  for (int y = 30; y < 50; ++y) {
    closed.MutableAt(-1, y) = kOccupied;
    closed.MutableAt(120, y) = kOccupied;
  }
  const ExploreDecision none = SelectNextTarget(closed, RobotAt(1.5, 2.0));
  EXPECT_TRUE(none.done());
  EXPECT_EQ(none.clusters, 0);

  // A wall across the room cuts the robot off from the right opening; the left one is closed.
  OccupancyGrid cut = RoomWithTwoOpenings();
  for (int y = 0; y < 80; ++y) {
    cut.MutableAt(60, y) = kOccupied;
  }
  for (int y = 30; y < 50; ++y) cut.MutableAt(-1, y) = kOccupied;
  const ExploreDecision unreachable = SelectNextTarget(cut, RobotAt(1.5, 2.0));
  EXPECT_TRUE(unreachable.done());
  EXPECT_EQ(unreachable.clusters, 1);
  EXPECT_EQ(unreachable.unreachable, 1);
}

// The search's node cap bounds the time of one plan; the frontiers beyond it are not out of reach,
// and the exploration is not done while one is left.
TEST(ExploreExplorerTest, FrontiersBeyondTheNodeCapAreStillReached) {
  OccupancyGrid grid = RoomWithTwoOpenings();
  for (int y = 30; y < 50; ++y) grid.MutableAt(-1, y) = kOccupied;  // only the right opening is left
  ExploreOptions options;
  options.planner.max_expanded_nodes = 500;  // a few of the room's 9600 cells
  const ExploreDecision decision = SelectNextTarget(grid, RobotAt(1.5, 2.0), options);
  ASSERT_FALSE(decision.done());
  EXPECT_NEAR(decision.target->position.x(), 5.975, 0.05);
  EXPECT_NEAR(decision.target->position.y(), 2.0, 0.05);
  EXPECT_FALSE(decision.search_truncated);
  EXPECT_GT(decision.expanded_nodes, 500u);
}

// Planning on the map with predictions merged in: a predicted wall across the room must not end
// the exploration when the robot's own map leaves the way to a frontier open.
TEST(ExploreExplorerTest, PredictedWallsAloneDoNotEndTheExploration) {
  OccupancyGrid built = RoomWithTwoOpenings();
  for (int y = 30; y < 50; ++y) built.MutableAt(-1, y) = kOccupied;  // the left opening is a wall
  OccupancyGrid merged = built;
  for (int y = 0; y < 80; ++y) merged.MutableAt(60, y) = kOccupied;  // a predicted wall across the room
  ASSERT_TRUE(SelectNextTarget(merged, RobotAt(1.5, 2.0)).done());

  const ExploreDecision decision = SelectNextTargetOnMerged(merged, built, RobotAt(1.5, 2.0));
  ASSERT_FALSE(decision.done());
  EXPECT_NEAR(decision.target->position.x(), 5.975, 0.05);  // the right opening
  EXPECT_NEAR(decision.target->position.y(), 2.0, 0.05);

  // Where the merged map has a target, it is the merged map's.
  OccupancyGrid open = built;
  for (int y = 30; y < 50; ++y) open.MutableAt(-1, y) = OccupancyGrid::kUnknown;
  const ExploreDecision on_merged = SelectNextTargetOnMerged(open, built, RobotAt(1.5, 2.0));
  ASSERT_FALSE(on_merged.done());
  EXPECT_NEAR(on_merged.target->position.x(), 0.025, 1e-9);  // the left opening, nearer

  // With no frontier left on either map, the exploration is done.
  OccupancyGrid closed = built;
  for (int y = 30; y < 50; ++y) closed.MutableAt(120, y) = kOccupied;
  EXPECT_TRUE(SelectNextTargetOnMerged(closed, closed, RobotAt(1.5, 2.0)).done());
}

}  // namespace
}  // namespace pslam
