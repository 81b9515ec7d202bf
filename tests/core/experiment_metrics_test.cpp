// The measures the experiments report: Psi of predictions and maps against a reference, cropping
// maps, choosing frontier targets and quantiles of latencies.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pslam/experiment/map_similarity.hpp"
#include "pslam/experiment/prediction_latency.hpp"

namespace pslam {
namespace {

constexpr OccupancyGrid::Cell kOccupied = 3000, kFree = -2000;  // milli log-odds

// A 40 x 40-cell room: walls on the border, free inside.
OccupancyGrid Room() {
  OccupancyGrid grid(0.05);
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 40; ++x) grid.MutableAt(x, y) = (x == 0 || y == 0 || x == 39 || y == 39) ? kOccupied : kFree;
  }
  return grid;
}

std::vector<HypothesisCell> Column(int x, bool occupied) {
  std::vector<HypothesisCell> cells;
  for (int y = 1; y < 39; ++y) cells.push_back({{x, y}, occupied});
  return cells;
}

TEST(ExperimentMetricsTest, PredictionSimilarityFollowsEquationFive) {
  const OccupancyGrid room = Room();
  EXPECT_DOUBLE_EQ(PredictionSimilarity(Column(39, true), room), 1.0);   // the wall, predicted as a wall
  // A wall where there is none: only its two end cells lie within a cell of the room's walls.
  EXPECT_DOUBLE_EQ(PredictionSimilarity(Column(20, true), room), 2.0 / 38.0);
  // One cell off is within the tolerance, whether the true wall is among the predicted cells or
  // just outside them (a wall predicted along the edge of what was explored).
  std::vector<HypothesisCell> shifted = Column(38, true);
  for (const HypothesisCell& c : Column(39, false)) shifted.push_back(c);
  EXPECT_DOUBLE_EQ(PredictionSimilarity(shifted, room), 1.0);
  EXPECT_DOUBLE_EQ(PredictionSimilarity(Column(38, true), room), 1.0);
  EXPECT_DOUBLE_EQ(PredictionSimilarity(Column(37, true), room), 2.0 / 38.0);  // two cells off
  EXPECT_DOUBLE_EQ(PredictionSimilarity(Column(20, false), room), 0.0);  // free vs free: no structure
  EXPECT_TRUE(std::isnan(PredictionSimilarity(Column(80, true), room)));  // nothing the reference knows
}

TEST(ExperimentMetricsTest, PooledCellsScoreAsThePapersCoarserGrid) {
  const OccupancyGrid pooled = PoolGrid(Room(), 2);  // 20 x 20 cells of 0.1 m
  EXPECT_DOUBLE_EQ(pooled.resolution(), 0.1);
  EXPECT_GT(pooled.At(19, 7), 0);   // the east wall (fine x = 39) shares a cell with free x = 38
  EXPECT_LT(pooled.At(18, 7), 0);
  EXPECT_FALSE(pooled.IsKnown(20, 7));
  const std::vector<HypothesisCell> column = PoolCells(Column(38, true), 2);
  ASSERT_EQ(column.size(), 20u);  // fine y = 1..38 pool into y = 0..19
  EXPECT_EQ(column.front().cell, Eigen::Vector2i(19, 0));
  const SimilarityOptions exact{CellStateThresholds{}, 0};
  // Here one fine cell off the wall is the same coarse cell; two fine cells off is not, but for
  // the two end cells, which share a coarse cell with the north and south walls.
  EXPECT_DOUBLE_EQ(PredictionSimilarity(column, pooled, exact), 1.0);
  EXPECT_DOUBLE_EQ(PredictionSimilarity(PoolCells(Column(36, true), 2), pooled, exact), 4.0 / 22.0);
  // Negative indices pool downwards, and any occupied cell makes the pooled cell occupied.
  const std::vector<HypothesisCell> mixed = PoolCells({{{-1, -1}, false}, {{-2, -2}, true}, {{0, 0}, false}}, 2);
  ASSERT_EQ(mixed.size(), 2u);
  EXPECT_EQ(mixed[0].cell, Eigen::Vector2i(-1, -1));
  EXPECT_TRUE(mixed[0].occupied);
  EXPECT_FALSE(mixed[1].occupied);
}

TEST(ExperimentMetricsTest, TransformCellsMovesCellCentres) {
  const std::vector<HypothesisCell> cells = Column(38, true);
  const std::vector<HypothesisCell> moved = TransformCells(cells, Pose2D(0.05, 0.0, 0.0), 0.05);
  ASSERT_EQ(moved.size(), cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) EXPECT_EQ(moved[i].cell, cells[i].cell + Eigen::Vector2i(1, 0));
  EXPECT_DOUBLE_EQ(PredictionSimilarity(moved, Room()), 1.0);  // the column moved onto the wall
  // Two cells landing on the same cell are kept once.
  const std::vector<HypothesisCell> squashed = TransformCells({{{0, 0}, true}, {{0, 0}, false}}, Pose2D(), 0.05);
  ASSERT_EQ(squashed.size(), 1u);
  EXPECT_TRUE(squashed[0].occupied);
}

TEST(ExperimentMetricsTest, BuiltMapSimilarityIgnoresWhatTheMapNeverSaw) {
  const OccupancyGrid room = Room();
  OccupancyGrid half(0.05);
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 20; ++x) half.MutableAt(x, y) = room.At(x, y);
  }
  EXPECT_DOUBLE_EQ(BuiltMapSimilarity(half, room), 1.0);
  half.MutableAt(10, 10) = kOccupied;  // a phantom obstacle
  EXPECT_LT(BuiltMapSimilarity(half, room), 1.0);
  EXPECT_NEAR(KnownArea(room), 40 * 40 * 0.05 * 0.05, 1e-9);
}

TEST(ExperimentMetricsTest, MappedOrPredictedCountsTheFreeAreaEitherAccountsFor) {
  const OccupancyGrid room = Room();  // 38 x 38 free cells inside the walls
  OccupancyGrid left_half(0.05);
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 20; ++x) left_half.MutableAt(x, y) = room.At(x, y);
  }
  EXPECT_DOUBLE_EQ(MappedOrPredictedFraction(room, room, {}), 1.0);
  EXPECT_DOUBLE_EQ(MappedOrPredictedFraction(room, left_half, {}), 19.0 / 38.0);  // x = 1..19 of 1..38
  std::vector<HypothesisCell> predicted;
  for (int x = 20; x < 30; ++x) {
    for (const HypothesisCell& c : Column(x, false)) predicted.push_back(c);
  }
  EXPECT_DOUBLE_EQ(MappedOrPredictedFraction(room, left_half, predicted), 29.0 / 38.0);
  // Predictions outside the reference's free area add nothing.
  EXPECT_DOUBLE_EQ(MappedOrPredictedFraction(room, left_half, Column(60, false)), 19.0 / 38.0);
}

TEST(ExperimentMetricsTest, CropKeepsOnlyTheBoxAndItsFrontiersBecomeTargets) {
  const OccupancyGrid crop = CropMap(Room(), CellBox{{0, 0}, {19, 39}});
  EXPECT_TRUE(crop.IsKnown(19, 20));
  EXPECT_FALSE(crop.IsKnown(20, 20));
  // The one open side of the half room is one cluster: its centre first, then cells along it.
  const std::vector<Eigen::Vector2i> one = FrontierTargets(crop, 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].x(), 19);
  EXPECT_NEAR(one[0].y(), 19.5, 1.0);
  const std::vector<Eigen::Vector2i> five = FrontierTargets(crop, 5);
  ASSERT_EQ(five.size(), 5u);
  for (std::size_t i = 0; i < five.size(); ++i) {
    EXPECT_EQ(five[i].x(), 19);
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(five[i].y(), five[j].y());
  }
  EXPECT_TRUE(FrontierTargets(Room(), 5).empty());  // a closed room has no frontier
}

TEST(ExperimentMetricsTest, QuantilesInterpolate) {
  EXPECT_DOUBLE_EQ(Quantile({}, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(Quantile({3.0, 1.0, 2.0}, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(Quantile({1.0, 2.0, 3.0, 4.0}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(Quantile({1.0, 2.0, 3.0, 4.0, 5.0}, 0.95), 4.8);
  EXPECT_DOUBLE_EQ(Quantile({7.0}, 0.95), 7.0);
}

}  // namespace
}  // namespace pslam
