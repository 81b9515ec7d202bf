// Laying a built map onto the true world: a map that is right but sits off as a whole is found
// where it belongs, and its Psi after alignment says it is right.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

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
  const Pose2D off{0.25, -0.20, 0.03};  // what a drift while mapping does to all mapped after it
  const OccupancyGrid built = TransformGrid(world, off);

  const MapAlignment alignment = AlignMap(built, world);
  const Pose2D residual = alignment.move * off;  // identity when the alignment undoes the offset
  EXPECT_LT(std::hypot(residual.x, residual.y), 0.05);
  EXPECT_LT(std::abs(residual.theta), 0.005);
  EXPECT_GT(alignment.centre_shift, 0.1);
  EXPECT_DOUBLE_EQ(alignment.psi, BuiltMapSimilarity(built, world));
  EXPECT_LT(alignment.psi, 0.6);
  EXPECT_GT(alignment.laid_psi, 0.9);
  EXPECT_DOUBLE_EQ(alignment.laid_psi, BuiltMapSimilarity(TransformGrid(built, alignment.move), world));
}

TEST(MapAlignmentTest, LeavesAMapThatIsInPlaceWhereItIs) {
  const OccupancyGrid world = World();
  const MapAlignment alignment = AlignMap(world, world);
  EXPECT_EQ(alignment.move.x, 0.0);
  EXPECT_EQ(alignment.move.y, 0.0);
  EXPECT_EQ(alignment.move.theta, 0.0);
  EXPECT_EQ(alignment.centre_shift, 0.0);
  EXPECT_DOUBLE_EQ(alignment.psi, 1.0);
  EXPECT_DOUBLE_EQ(alignment.laid_psi, 1.0);
}

TEST(MapAlignmentTest, AMapWithoutWallsStaysAsItLies) {
  OccupancyGrid empty(0.05);
  for (int x = 0; x < 10; ++x) empty.MutableAt(x, 0) = kFree;
  for (const OccupancyGrid& built : {empty, OccupancyGrid(0.05)}) {
    const MapAlignment alignment = AlignMap(built, World());
    EXPECT_EQ(alignment.centre_shift, 0.0);
    EXPECT_EQ(alignment.laid_psi, alignment.psi);
  }
  EXPECT_THROW(AlignMap(OccupancyGrid(0.1), World()), std::invalid_argument);
}

}  // namespace
}  // namespace pslam
