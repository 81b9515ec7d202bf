// Laying a built map onto the true world: a map that is right but sits off as a whole is found
// where it belongs, and its Psi after alignment says it is right.
#include <gtest/gtest.h>

#include <cmath>

#include "pslam/experiment/map_alignment.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/grid/grid_transform.hpp"

namespace pslam {
namespace {

constexpr OccupancyGrid::Cell kOccupied = 3000, kFree = -2000;  // milli log-odds

// A 6 x 4 m room with two blocks of different sizes inside, so that only one pose fits.
OccupancyGrid World() {
  OccupancyGrid grid(0.05);
  for (int y = 0; y < 80; ++y) {
    for (int x = 0; x < 120; ++x) {
      const bool border = x == 0 || y == 0 || x == 119 || y == 79;
      const bool block_a = x >= 20 && x < 40 && y >= 20 && y < 30;
      const bool block_b = x >= 70 && x < 80 && y >= 40 && y < 65;
      grid.MutableAt(x, y) = border || block_a || block_b ? kOccupied : kFree;
    }
  }
  return grid;
}

TEST(MapAlignmentTest, FindsWhereAMapThatSitsOffAsAWholeBelongs) {
  const OccupancyGrid world = World();
  const Pose2D off{0.25, -0.20, 0.03};  // what a drifting start would do to the whole map
  const OccupancyGrid built = TransformGrid(world, off);
  EXPECT_LT(BuiltMapSimilarity(built, world), 0.6);

  const MapAlignment alignment = AlignMap(built, world);
  ASSERT_TRUE(alignment.found);
  const Pose2D residual = alignment.move * off;  // identity when the alignment undoes the offset
  EXPECT_LT(std::hypot(residual.x, residual.y), 0.05);
  EXPECT_LT(std::abs(residual.theta), 0.005);
  EXPECT_GT(alignment.centre_shift, 0.1);
  EXPECT_GT(BuiltMapSimilarity(TransformGrid(built, alignment.move), world), 0.9);
}

TEST(MapAlignmentTest, LeavesAMapThatIsInPlaceWhereItIs) {
  const OccupancyGrid world = World();
  const MapAlignment alignment = AlignMap(world, world);
  ASSERT_TRUE(alignment.found);
  EXPECT_LT(std::hypot(alignment.move.x, alignment.move.y), 1e-9);
  EXPECT_LT(std::abs(alignment.move.theta), 1e-9);
  EXPECT_GT(alignment.score, 0.9);
}

TEST(MapAlignmentTest, AMapWithoutWallsHasNothingToAlign) {
  OccupancyGrid empty(0.05);
  for (int x = 0; x < 10; ++x) empty.MutableAt(x, 0) = kFree;
  EXPECT_FALSE(AlignMap(empty, World()).found);
  EXPECT_FALSE(AlignMap(OccupancyGrid(0.05), World()).found);
}

}  // namespace
}  // namespace pslam
