// Coverage of unexplored cells by overlapping hypotheses.
#include <gtest/gtest.h>

#include "pslam/slam/prediction_coverage.hpp"

namespace pslam {
namespace {

TEST(PredictionCoverageTest, WithdrawingOneHypothesisKeepsWhatAnotherCovers) {
  PredictionCoverage coverage(0.05);
  const std::vector<HypothesisCell> a = {{{0, 0}, false}, {{1, 0}, true}};
  const std::vector<HypothesisCell> b = {{{1, 0}, true}, {{2, 0}, false}};
  coverage.Add(a);
  coverage.Add(b);
  EXPECT_TRUE(coverage.Covered({1, 0}));
  EXPECT_TRUE(coverage.PredictedWall({1, 0}));
  EXPECT_FALSE(coverage.PredictedWall({0, 0}));

  coverage.Remove(a);
  EXPECT_FALSE(coverage.Covered({0, 0}));
  EXPECT_TRUE(coverage.Covered({1, 0}));  // b still covers it
  EXPECT_TRUE(coverage.PredictedWall({1, 0}));
  EXPECT_TRUE(coverage.Covered({2, 0}));

  coverage.Remove(b);
  EXPECT_FALSE(coverage.Covered({1, 0}));
  EXPECT_FALSE(coverage.PredictedWall({1, 0}));
  EXPECT_FALSE(coverage.Covered({5, 5}));
}

}  // namespace
}  // namespace pslam
