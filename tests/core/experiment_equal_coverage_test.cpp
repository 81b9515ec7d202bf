// Exploration time compared at equal coverage: a skip-predicted run that stops before mapping or
// predicting what full coverage did saves nothing, however short it was; one that gets there is
// timed to that point, as is full coverage; coverage counts only free space reachable from the start.
#include <gtest/gtest.h>

#include <cmath>

#include "pslam/experiment/equal_coverage.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

CoverageTrace Trace(std::vector<std::pair<double, double>> samples) { return CoverageTrace{std::move(samples)}; }

TEST(EqualCoverageTest, SkipRunThatStopsEarlySavesNothing) {
  // Full coverage hit 70 % after 2400 s; skip stopped at 790 s with 41 % mapped or predicted.
  const CoverageTrace full = Trace({{400.0, 0.30}, {1200.0, 0.55}, {2400.0, 0.70}});
  const CoverageTrace skip = Trace({{400.0, 0.35}, {790.0, 0.41}});
  const EqualCoverageSaving s = CompareAtEqualCoverage(full, skip, 0.02);
  EXPECT_FALSE(s.skip_reached);
  EXPECT_TRUE(std::isnan(s.skip_time_s));
  EXPECT_DOUBLE_EQ(s.saved_fraction, 0.0);
  EXPECT_NEAR(s.target, 0.68, 1e-12);
  EXPECT_DOUBLE_EQ(s.full_time_s, 2400.0);
}

TEST(EqualCoverageTest, BothRunsAreTimedToTheCoverageFullReached) {
  // Full reaches 97.5 % at 700 s and spends 150 s more on scraps; skip reaches 98 % at 420 s.
  const CoverageTrace full = Trace({{300.0, 0.60}, {700.0, 0.975}, {850.0, 0.99}});
  const CoverageTrace skip = Trace({{300.0, 0.80}, {420.0, 0.98}, {430.0, 0.98}});
  const EqualCoverageSaving s = CompareAtEqualCoverage(full, skip, 0.02);
  EXPECT_TRUE(s.skip_reached);
  EXPECT_DOUBLE_EQ(s.full_time_s, 700.0);
  EXPECT_DOUBLE_EQ(s.skip_time_s, 420.0);
  EXPECT_NEAR(s.saved_fraction, 280.0 / 700.0, 1e-12);
}

TEST(EqualCoverageTest, SlowerSkipRunSavesANegativeShare) {
  const CoverageTrace full = Trace({{500.0, 1.0}});
  const CoverageTrace skip = Trace({{600.0, 0.99}});
  EXPECT_NEAR(CompareAtEqualCoverage(full, skip, 0.02).saved_fraction, -0.2, 1e-12);
}

TEST(EqualCoverageTest, CoverageCountsOnlyFreeSpaceReachableFromTheStart) {
  // Two rooms side by side with a solid wall between them: only the start's room counts.
  World world = MakeWalledRoom(8.0, 4.0, 0.2, 0.05);
  FillBox(world, {4.0, 0.0}, {4.2, 4.0}, WorldCell::kOccupied);
  const OccupancyGrid reachable = ReachableFreeCells(world, {1.0, 1.0});
  OccupancyGrid built(0.05);
  for (int y = 0; y < 80; ++y) {
    for (int x = 0; x < 80; ++x) built.MutableAt(x, y) = -1000;  // the start's room, mapped
  }
  EXPECT_NEAR(MappedOrPredictedFraction(reachable, built, {}), 1.0, 1e-12);
  // Against the whole world, the unreachable room would count as missed.
  EXPECT_LT(MappedOrPredictedFraction(world.ToGrid(), built, {}), 0.55);
}

}  // namespace
}  // namespace pslam
