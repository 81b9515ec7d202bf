#include "pslam/grid/occupancy_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pslam/grid/ray_caster.hpp"
#include "pslam/grid/scan_inserter.hpp"
#include "testing/synthetic_world.hpp"

namespace pslam {
namespace {

TEST(OccupancyGrid, UnknownUntilWrittenAndGrowsInEveryDirection) {
  OccupancyGrid grid(0.05);
  EXPECT_FALSE(grid.IsKnown(0, 0));
  EXPECT_FLOAT_EQ(grid.Probability(0, 0), 0.5f);
  grid.AddLogOdds(-300, 500, 800, -2000, 3500);
  grid.AddLogOdds(700, -90, -400, -2000, 3500);
  EXPECT_TRUE(grid.IsKnown(-300, 500));
  EXPECT_GT(grid.Probability(-300, 500), 0.68f);
  EXPECT_LT(grid.Probability(700, -90), 0.41f);
  const CellBox box = grid.KnownBounds();
  EXPECT_EQ(box.min, Eigen::Vector2i(-300, -90));
  EXPECT_EQ(box.max, Eigen::Vector2i(700, 500));
  EXPECT_EQ(grid.AllocatedTiles(), 2u);
}

TEST(OccupancyGrid, ClampsLogOdds) {
  OccupancyGrid grid(0.05);
  for (int i = 0; i < 100; ++i) grid.AddLogOdds(3, 4, 850, -2000, 3500);
  EXPECT_NEAR(grid.LogOdds(3, 4), 3.5f, 1e-6);
}

TEST(OccupancyGrid, CopiesShareTilesUntilWritten) {
  OccupancyGrid a(0.05);
  for (int x = 0; x < 640; x += 8) a.AddLogOdds(x, 0, 500, -2000, 3500);
  const std::size_t tiles = a.AllocatedTiles();
  OccupancyGrid b = a;
  EXPECT_LT(b.UniqueBytes(), sizeof(OccupancyGrid::Tile));  // nothing of its own yet
  b.AddLogOdds(1, 0, 500, -2000, 3500);                     // writes one tile
  EXPECT_EQ(b.UniqueBytes() / sizeof(OccupancyGrid::Tile), 1u);
  EXPECT_FLOAT_EQ(a.LogOdds(1, 0), 0.0f);                   // the original is untouched
  EXPECT_FALSE(a.IsKnown(1, 0));
  EXPECT_TRUE(b.IsKnown(1, 0));
  // Writing to the original after the copy must not leak into the copy either.
  a.AddLogOdds(8, 0, 500, -2000, 3500);
  EXPECT_FLOAT_EQ(b.LogOdds(8, 0), 0.5f);
  EXPECT_EQ(a.AllocatedTiles(), tiles);
}

TEST(RayCaster, VisitsEveryCellOnceExcludingTheEnd) {
  std::vector<Eigen::Vector2i> cells;
  TraceRay({0, 0}, {5, 2}, [&](int x, int y) { cells.emplace_back(x, y); });
  ASSERT_EQ(cells.size(), 5u);
  EXPECT_EQ(cells.front(), Eigen::Vector2i(0, 0));
  for (std::size_t i = 1; i < cells.size(); ++i) EXPECT_LE((cells[i] - cells[i - 1]).cwiseAbs().maxCoeff(), 1);
  cells.clear();
  TraceRay({3, 3}, {3, -4}, [&](int x, int y) { cells.emplace_back(x, y); });
  ASSERT_EQ(cells.size(), 7u);
  EXPECT_EQ(cells.back(), Eigen::Vector2i(3, -3));
}

TEST(ScanInserter, MarksWallsOccupiedAndTheRoomFree) {
  OccupancyGrid grid(0.05);
  const ScanInserter inserter;
  const auto walls = testing::RoomWalls();
  const LaserScan scan = testing::RenderScan(Pose2D(0, 0, 0), walls, Pose2D());
  inserter.Insert(ToScanPoints(scan, {}), Pose2D(0, 0, 0), grid);
  // Straight ahead the beam hits the wall at x = 5 (or the pillar at x = 1 is off-axis).
  const Eigen::Vector2i wall = grid.WorldToCell({5.0 - 1e-6, 0.0});  // the endpoint rounds to either side
  EXPECT_GT(std::max(grid.Probability(wall.x(), wall.y()), grid.Probability(wall.x() + 1, wall.y())), 0.6f);
  const Eigen::Vector2i free = grid.WorldToCell({3.0, 0.0});
  EXPECT_LT(grid.Probability(free.x(), free.y()), 0.45f);
  const Eigen::Vector2i behind = grid.WorldToCell({-3.0, 0.0});  // behind the 180 degree sensor
  EXPECT_FALSE(grid.IsKnown(behind.x(), behind.y()));
}

// A scan taken 1e15 m away (finite, absurd odometry) must neither overflow the cell index nor
// grow the tile table towards it: the writes are refused and counted, the map stays as it was.
// A wall along y = 2 m (its row of cells, y 2.00-2.05 m, marked occupied), seen from (0, 1) at
// shallow angles by a scan whose endpoints lie 2 mm into the next row, as a pose a few millimetres
// off puts them. Returns how many of the wall's cells between x = 2 m and 8 m the scan made less
// likely occupied.
int WallCellsClearedByGrazingBeams(bool grazing_stop) {
  OccupancyGrid grid(0.05);
  for (int x = 0; x < 200; ++x) grid.AddLogOdds(x, 40, 2000, -2000, 3500);
  ScanPoints points;
  for (double x = 3.0; x <= 8.0; x += 0.25) points.hits.emplace_back(static_cast<float>(x), 1.052f);
  ScanInsertOptions options;
  options.grazing_stop = grazing_stop;
  ScanInserter(options).Insert(points, Pose2D(0.0, 1.0, 0.0), grid);
  int cleared = 0;
  for (int x = 40; x < 160; ++x) cleared += grid.At(x, 40) < 2000;
  return cleared;
}

TEST(ScanInserter, BeamsGrazingAWallStopShortOfClearingIt) {
  const int without = WallCellsClearedByGrazingBeams(false);
  const int with = WallCellsClearedByGrazingBeams(true);
  EXPECT_GE(without, 60) << "each beam runs through the wall's row before its endpoint";
  EXPECT_LE(with, without / 2) << with << " of " << without;
}

TEST(OccupancyGrid, RefusesCellsBeyondItsExtentWithoutAllocating) {
  OccupancyGrid grid(0.05);
  const ScanInserter inserter;
  const LaserScan scan = testing::RenderScan(Pose2D(0, 0, 0), testing::RoomWalls(), Pose2D());
  inserter.Insert(ToScanPoints(scan, {}), Pose2D(0, 0, 0), grid);
  const std::size_t tiles = grid.AllocatedTiles();
  const int wide = grid.tiles_wide(), high = grid.tiles_high();
  EXPECT_EQ(grid.refused_writes(), 0u);

  const Eigen::Vector2i far = grid.WorldToCell({1e15, -1e15});
  EXPECT_EQ(far, Eigen::Vector2i(OccupancyGrid::kMaxCellIndex, -OccupancyGrid::kMaxCellIndex));
  EXPECT_EQ(grid.WorldToCell({std::nan(""), 0.0}).x(), -OccupancyGrid::kMaxCellIndex);
  inserter.Insert(ToScanPoints(scan, {}), Pose2D(1e15, 1e15, 0), grid);
  inserter.Insert(ToScanPoints(scan, {}), Pose2D(2e5, 0, 0), grid);  // beyond the default 1e5 m
  EXPECT_GT(grid.refused_writes(), 0u);
  EXPECT_FALSE(grid.IsKnown(far.x(), far.y()));
  EXPECT_EQ(grid.AllocatedTiles(), tiles);
  EXPECT_EQ(grid.tiles_wide(), wide);
  EXPECT_EQ(grid.tiles_high(), high);
  OccupancyGrid copy = grid;  // copies keep the bound and the count
  EXPECT_EQ(copy.refused_writes(), grid.refused_writes());
}

// Within the extent, a jump of 20 km (millimetres read as metres) would make the dense tile table
// span both places: 6250 x 6250 slots at 5 cm. The table bound refuses that growth instead.
TEST(OccupancyGrid, RefusesGrowthPastTheTileTableBound) {
  OccupancyGrid grid(0.05, GridLimits{.max_extent_meters = 1e5, .max_tile_slots = 4096});
  grid.AddLogOdds(0, 0, 500, -2000, 3500);
  grid.AddLogOdds(20 * 64 - 1, 20 * 64 - 1, 500, -2000, 3500);  // 20 x 20 tiles: fits, with or without margin
  EXPECT_EQ(grid.refused_writes(), 0u);
  const Eigen::Vector2i jump = grid.WorldToCell({20000.0, 20000.0});
  grid.AddLogOdds(jump.x(), jump.y(), 500, -2000, 3500);
  EXPECT_EQ(grid.refused_writes(), 1u);
  EXPECT_FALSE(grid.IsKnown(jump.x(), jump.y()));
  EXPECT_LE(static_cast<std::size_t>(grid.tiles_wide()) * grid.tiles_high(), 4096u);
  EXPECT_TRUE(grid.IsKnown(0, 0));
  // Normal growth near the map goes on.
  grid.AddLogOdds(-64, -64, 500, -2000, 3500);
  EXPECT_TRUE(grid.IsKnown(-64, -64));
  EXPECT_EQ(grid.refused_writes(), 1u);
}

}  // namespace
}  // namespace pslam
