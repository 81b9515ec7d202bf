// The true world as a laser could ever map it from inside: what predictions are scored against
// besides the whole truth, so that the inside of a solid block no run can see is told apart from
// mistakes a run could see.
#include <gtest/gtest.h>

#include <vector>

#include "pslam/experiment/equal_coverage.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/experiment/observable_truth.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

// An 8 x 4 m room (walls 0.2 m thick outside it) and a solid 1 x 1 m block at (3, 1.5)-(4, 2.5), 5 cm cells.
World RoomWithBlock() {
  World world = MakeWalledRoom(8.0, 4.0, 0.2, 0.05);
  FillBox(world, {3.0, 1.5}, {4.0, 2.5}, WorldCell::kOccupied);
  return world;
}

TEST(ObservableTruthTest, KeepsReachableFloorAndTheFacesAroundIt) {
  const World world = RoomWithBlock();
  const OccupancyGrid truth = world.ToGrid();
  const OccupancyGrid observable = ObservableTruth(world, ReachableFreeCells(world, {1.0, 1.0}));
  const Eigen::Vector2i floor = world.WorldToCell({1.0, 1.0});
  const Eigen::Vector2i block_face = world.WorldToCell({3.01, 2.0});
  const Eigen::Vector2i block_inside = world.WorldToCell({3.5, 2.0});
  const Eigen::Vector2i outer_wall_outside = world.WorldToCell({-0.19, 2.0});
  ASSERT_TRUE(truth.IsKnown(block_inside.x(), block_inside.y()));
  ASSERT_TRUE(truth.IsKnown(outer_wall_outside.x(), outer_wall_outside.y()));

  EXPECT_LT(observable.At(floor.x(), floor.y()), 0);
  EXPECT_GT(observable.At(block_face.x(), block_face.y()), 0);
  EXPECT_FALSE(observable.IsKnown(block_inside.x(), block_inside.y()));
  EXPECT_FALSE(observable.IsKnown(outer_wall_outside.x(), outer_wall_outside.y()));
}

TEST(ObservableTruthTest, FloorPredictedInsideASolidBlockCountsOnlyAgainstTheWholeTruth) {
  const World world = RoomWithBlock();
  const OccupancyGrid observable = ObservableTruth(world, ReachableFreeCells(world, {1.0, 1.0}));
  // The block predicted as a room of the same outline: its walls where the block's faces are.
  const Eigen::Vector2i min = world.WorldToCell({3.0, 1.5});
  const Eigen::Vector2i max = world.WorldToCell({3.99, 2.49});
  std::vector<HypothesisCell> predicted;
  for (int y = min.y() - 5; y <= max.y() + 5; ++y) {
    for (int x = min.x() - 5; x <= max.x() + 5; ++x) {
      const bool inside = x >= min.x() && x <= max.x() && y >= min.y() && y <= max.y();
      const bool face = inside && (x == min.x() || x == max.x() || y == min.y() || y == max.y());
      predicted.push_back({{x, y}, face});
    }
  }
  EXPECT_NEAR(PredictionSimilarity(predicted, observable), 1.0, 1e-9);
  EXPECT_LT(PredictionSimilarity(predicted, world.ToGrid()), 0.5);
}

}  // namespace
}  // namespace pslam
