// Frontier cells and clusters on tiny hand-made grids.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "pslam/explore/frontier.hpp"

namespace pslam {
namespace {

constexpr int kFree = -2000;     // milli log-odds: p = 0.12
constexpr int kOccupied = 3000;  // p = 0.95
constexpr int kOneMiss = -405;   // p = 0.40: a single miss of the default inserter, still uncertain

// '.' free, '#' occupied, '~' seen once (uncertain), anything else unknown. The first row is the
// top (highest y); cell (0, 0) is the bottom-left character.
OccupancyGrid FromAscii(const std::vector<std::string>& rows) {
  OccupancyGrid grid(0.05);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const int y = static_cast<int>(rows.size() - 1 - r);
    for (std::size_t x = 0; x < rows[r].size(); ++x) {
      const char c = rows[r][x];
      if (c == '.') grid.MutableAt(static_cast<int>(x), y) = kFree;
      if (c == '#') grid.MutableAt(static_cast<int>(x), y) = kOccupied;
      if (c == '~') grid.MutableAt(static_cast<int>(x), y) = kOneMiss;
    }
  }
  return grid;
}

bool Contains(const std::vector<Eigen::Vector2i>& cells, const Eigen::Vector2i& c) {
  return std::find(cells.begin(), cells.end(), c) != cells.end();
}

TEST(ExploreFrontierTest, FreeCellsNextToUnknownAreFrontier) {
  const OccupancyGrid grid = FromAscii({
      "#######",
      "#.....?",
      "#.....?",
      "#.#...#",
      "#######",
  });
  const auto cells = FindFrontierCells(grid);
  ASSERT_EQ(cells.size(), 2u);
  EXPECT_TRUE(Contains(cells, {5, 3}));
  EXPECT_TRUE(Contains(cells, {5, 2}));
}

TEST(ExploreFrontierTest, UncertainCellsCountAsUnknownAndDiagonalsDoNot) {
  const OccupancyGrid grid = FromAscii({
      "#####",
      "#...~",
      "#...#",
      "#..#?",
      "#####",
  });
  // (3, 3) touches the uncertain cell; (3, 2) touches '?' only diagonally: not a frontier.
  const auto cells = FindFrontierCells(grid);
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_EQ(cells[0], Eigen::Vector2i(3, 3));
}

TEST(ExploreFrontierTest, ClustersAreConnectedComponentsWithCentroidAndSize) {
  const OccupancyGrid grid = FromAscii({
      "##??#########",
      "#...........?",
      "#...........?",
      "#...........?",
      "#############",
  });
  FrontierOptions options;
  options.min_cluster_cells = 1;
  const auto clusters = FindFrontierClusters(grid, options);
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_EQ(clusters[0].size(), 3u);  // the right opening, largest first
  EXPECT_NEAR(clusters[0].centroid.x(), 11.5 * 0.05, 1e-9);
  EXPECT_NEAR(clusters[0].centroid.y(), 2.5 * 0.05, 1e-9);
  EXPECT_EQ(clusters[1].size(), 2u);  // the top opening
  EXPECT_NEAR(clusters[1].centroid.x(), 3.0 * 0.05, 1e-9);
  EXPECT_NEAR(clusters[1].centroid.y(), 3.5 * 0.05, 1e-9);

  options.min_cluster_cells = 3;  // small clusters are dropped
  EXPECT_EQ(FindFrontierClusters(grid, options).size(), 1u);
}

TEST(ExploreFrontierTest, ClosedRoomHasNoFrontier) {
  const OccupancyGrid grid = FromAscii({
      "#####",
      "#...#",
      "#####",
  });
  EXPECT_TRUE(FindFrontierCells(grid).empty());
  EXPECT_TRUE(FindFrontierClusters(grid).empty());
  EXPECT_TRUE(FindFrontierClusters(OccupancyGrid(0.05)).empty());
}

}  // namespace
}  // namespace pslam
