// Where in a cell its hits landed (OccupancyGrid::AddHit) and scan matching that reads evidence
// there (ScanMatchOptions::hit_offsets). The maze's walls lie on the edges of the map's cells: a
// match on cell centres pulls each endpoint half a cell into its wall, and at the maze's start,
// where one side of the corridor is a solid wall and the other has openings, that pull turns the
// scan.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/grid/scan_inserter.hpp"
#include "pslam/matching/scan_matcher.hpp"
#include "pslam/sim/laser_model.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {
namespace {

TEST(OccupancyGridHits, KeepTheMeanOfWhereTheyLandedSinceTheCellTurnedOccupied) {
  OccupancyGrid grid(0.05);
  EXPECT_EQ(grid.HitOffset(3, 4), Eigen::Vector2f::Zero());
  grid.AddHit(3, 4, {0.4f, -0.2f}, 850, -2000, 3500);
  grid.AddHit(3, 4, {0.2f, -0.4f}, 850, -2000, 3500);
  EXPECT_NEAR(grid.HitOffset(3, 4).x(), 0.3f, 0.005f);
  EXPECT_NEAR(grid.HitOffset(3, 4).y(), -0.3f, 0.005f);
  EXPECT_GT(grid.LogOdds(3, 4), 1.6f);  // the log-odds rise as AddLogOdds would raise them

  // Cleared to free, then hit again: the old surface is gone, the new hit alone says where it is.
  grid.AddLogOdds(3, 4, -5000, -2000, 3500);
  grid.AddHit(3, 4, {-0.45f, 0.1f}, 850, -2000, 3500);
  EXPECT_NEAR(grid.HitOffset(3, 4).x(), -0.45f, 0.005f);
  EXPECT_NEAR(grid.HitOffset(3, 4).y(), 0.1f, 0.005f);
}

TEST(OccupancyGridHits, CopiesKeepTheirOwnOffsets) {
  OccupancyGrid grid(0.05);
  grid.AddHit(0, 0, {0.25f, 0.25f}, 850, -2000, 3500);
  OccupancyGrid copy = grid;
  copy.AddHit(0, 0, {-0.25f, -0.25f}, 850, -2000, 3500);
  EXPECT_NEAR(grid.HitOffset(0, 0).x(), 0.25f, 0.005f);
  EXPECT_NEAR(copy.HitOffset(0, 0).x(), 0.0f, 0.005f);
}

struct HeadingErrors {
  double mean = 0.0;      // signed: a bias
  double mean_abs = 0.0;
};

// Maps the maze's first corridor from 30 true poses, then matches 40 scans from random true poses
// near the start, each starting at its true pose with the wheels' prior on translation (as the
// simulated explorations match): a match that is right stays there.
HeadingErrors MatchAtTheMazeStart(bool hit_offsets) {
  const World maze = LoadWorld(std::string(PSLAM_SOURCE_DIR) + "/core/worlds/maze.yaml");
  const LaserOptions laser;
  const ScanPointsOptions points{.max_usable_range = laser.max_range, .no_return_free_range = laser.max_range - 0.1};
  std::mt19937_64 rng(7);
  OccupancyGrid grid(0.05);
  const ScanInserter inserter;
  for (int k = 0; k < 30; ++k) {
    const Pose2D pose(1.1 + 0.03 * k, 1.1, 0.02 * k);
    inserter.Insert(ToScanPoints(SimulateScan(maze, pose, laser, rng), points), pose, grid);
  }
  const ScanMatchOptions options{
      .coarsest_level = 3, .degenerate_ratio = 0.15, .prior_translation_weight = 30.0, .hit_offsets = hit_offsets};
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  HeadingErrors errors;
  constexpr int kScans = 40;
  for (int n = 0; n < kScans; ++n) {
    const Pose2D truth(1.2 + 0.05 * unit(rng), 1.1 + 0.05 * unit(rng), 0.15 * unit(rng));
    const ScanPoints scan = ToScanPoints(SimulateScan(maze, truth, laser, rng), points);
    const double error = NormalizeAngle(MatchScan(grid, scan.hits, truth, options).pose.theta - truth.theta);
    errors.mean += error / kScans;
    errors.mean_abs += std::abs(error) / kScans;
  }
  return errors;
}

TEST(ScanMatcherHitOffsets, RemoveTheTurnThatWallsOnCellEdgesCause) {
  const HeadingErrors centres = MatchAtTheMazeStart(false);
  const HeadingErrors offsets = MatchAtTheMazeStart(true);
  // On cell centres every match turns the same way, by a quarter of a degree.
  EXPECT_LT(centres.mean, -0.003) << "the bias these offsets remove is not there any more";
  EXPECT_LT(std::abs(offsets.mean), 0.001);
  EXPECT_LT(offsets.mean_abs, 0.25 * centres.mean_abs);
}

}  // namespace
}  // namespace pslam
