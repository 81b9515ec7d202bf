#include "pslam/predict/similarity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "pslam/predict/alignment.hpp"
#include "pslam/predict/predictor_options.hpp"
#include "pslam/predict/region_matcher.hpp"
#include "pslam/predict/structure_predictor.hpp"

namespace pslam {
namespace {

// A 'w' x 'h' raster, all free: an explored, empty room.
CellRaster FreeRaster(int w = 40, int h = 30) { return CellRaster({0, 0}, w, h, CellState::kFree); }

void HorizontalWall(CellRaster& r, int y, int x0, int x1) {
  for (int x = x0; x <= x1; ++x) r.Local(x, y) = CellState::kOccupied;
}
void VerticalWall(CellRaster& r, int x, int y0, int y1) {
  for (int y = y0; y <= y1; ++y) r.Local(x, y) = CellState::kOccupied;
}

TEST(PredictSimilarity, IdenticalRegionsScoreOne) {
  CellRaster a = FreeRaster();
  HorizontalWall(a, 3, 2, 30);
  VerticalWall(a, 2, 3, 25);
  VerticalWall(a, 17, 10, 20);
  for (int tolerance : {0, 1, 2}) EXPECT_DOUBLE_EQ(Similarity(a, a, tolerance), 1.0) << tolerance;
}

TEST(PredictSimilarity, DisjointStructuresScoreZero) {
  CellRaster a = FreeRaster(), b = FreeRaster();
  HorizontalWall(a, 3, 2, 30);
  HorizontalWall(b, 20, 2, 30);  // 17 cells away: disjoint even with the tolerance
  VerticalWall(b, 37, 5, 25);
  for (int tolerance : {0, 1, 2}) EXPECT_DOUBLE_EQ(Similarity(a, b, tolerance), 0.0) << tolerance;
}

TEST(PredictSimilarity, NoStructureOnEitherSideScoresZero) {
  EXPECT_DOUBLE_EQ(Similarity(FreeRaster(), FreeRaster()), 0.0);
}

// The reason for eq. 3-5: two rooms with the same free space but different walls agree on almost
// every cell, yet Psi, which only counts occupied cells, must find them dissimilar.
TEST(PredictSimilarity, SharedFreeSpaceDoesNotInflatePsi) {
  CellRaster a = FreeRaster(100, 100), b = FreeRaster(100, 100);
  HorizontalWall(a, 0, 0, 99);   // a: walls south and west
  VerticalWall(a, 0, 0, 99);
  HorizontalWall(b, 99, 0, 99);  // b: walls north and east
  VerticalWall(b, 99, 0, 99);
  int same = 0;
  for (std::size_t i = 0; i < a.cells.size(); ++i) same += a.cells[i] == b.cells[i];
  EXPECT_GT(static_cast<double>(same) / static_cast<double>(a.cells.size()), 0.95);  // what an all-cell measure sees
  EXPECT_LT(Similarity(a, b), 0.1);  // only the two shared corner cells and their neighbours match
  EXPECT_LT(Similarity(a, b, 0), 0.1);
}

TEST(PredictSimilarity, OnlyTheExploredPartOfTheTargetCounts) {
  CellRaster target = FreeRaster(), reference = FreeRaster();
  HorizontalWall(target, 3, 2, 30);
  HorizontalWall(reference, 3, 2, 30);
  VerticalWall(reference, 35, 5, 25);  // structure where the target is unexplored ...
  for (int y = 0; y < target.height; ++y) {
    for (int x = 33; x < target.width; ++x) target.Local(x, y) = CellState::kUnknown;
  }
  EXPECT_DOUBLE_EQ(Similarity(target, reference), 1.0);  // ... is what we predict, not a mismatch
  const OverlapCounts counts = CountOverlap(target, reference, 1);
  EXPECT_EQ(counts.target_occupied, 29);
  EXPECT_EQ(counts.aligned_occupied, 29);
}

TEST(PredictSimilarity, ToleranceForgivesOneCellOfMisalignment) {
  CellRaster a = FreeRaster(), b = FreeRaster();
  HorizontalWall(a, 10, 2, 30);
  HorizontalWall(b, 11, 2, 30);
  EXPECT_DOUBLE_EQ(Similarity(a, b, 0), 0.0);  // eq. 5 exactly
  EXPECT_DOUBLE_EQ(Similarity(a, b, 1), 1.0);
}

TEST(PredictSimilarity, RejectsRastersOfDifferentSize) {
  EXPECT_THROW(Similarity(FreeRaster(10, 10), FreeRaster(10, 11)), std::invalid_argument);
}

TEST(PredictAlignment, GammaMapsReferenceControlPointOntoTargetAndRotatesByTheta) {
  const Eigen::Vector2d p1(12.5, -3.0), p2(-4.0, 7.25);
  const double theta = 0.7;
  const Pose2D gamma = AlignmentTransform(p1, p2, theta);
  EXPECT_NEAR((gamma * p2 - p1).norm(), 0.0, 1e-12);
  const Eigen::Vector2d u(std::cos(0.2), std::sin(0.2));  // a direction at the reference point ...
  const Eigen::Vector2d mapped = gamma * Eigen::Vector2d(p2 + 3.0 * u) - p1;
  EXPECT_NEAR(std::atan2(mapped.y(), mapped.x()), 0.2 + theta, 1e-12);  // ... turns by theta
  EXPECT_NEAR(mapped.norm(), 3.0, 1e-12);                               // rigidly
  EXPECT_NEAR(gamma.theta, theta, 1e-12);

  // The cell-coordinate form agrees, and ToReference inverts ToTarget.
  const Alignment alignment{p1, p2, theta};
  const Eigen::Vector2d q(1.0, 2.0);
  EXPECT_NEAR((alignment.ToTarget(q) - gamma * q).norm(), 0.0, 1e-12);
  EXPECT_NEAR((alignment.ToReference(alignment.ToTarget(q)) - q).norm(), 0.0, 1e-12);
  // Eq. 2's translation column is P1 - P2 in coordinates centred on P2.
  EXPECT_NEAR((alignment.ToTarget(p2 + q) - (Eigen::Rotation2Dd(theta) * q + p2 + (p1 - p2))).norm(), 0.0, 1e-12);
}

TEST(PredictRegionMatcher, CoarsePsiEstimatesPsiOnAQuarterOfTheCells) {
  // A window of rooms; S_f is a copy of its middle. Aligned onto itself both scores are 1, and a
  // misalignment scores about the same on the sampled quarter as on every cell.
  CellRaster window = FreeRaster(120, 120);
  for (int k = 0; k <= 120; k += 20) {
    if (k < 120) HorizontalWall(window, k, 0, 119);
    if (k < 120) VerticalWall(window, k, 0, 119);
  }
  VerticalWall(window, 47, 30, 90);  // something off the lattice
  CellRaster target({30, 30}, 60, 60, CellState::kFree);
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 60; ++x) target.Local(x, y) = window.Local(x + 30, y + 30);
  }
  const RegionMatcher matcher(window, target, 1);
  const Alignment same{{60.0, 60.0}, {60.0, 60.0}, 0.0};
  EXPECT_DOUBLE_EQ(matcher.Psi(same), 1.0);
  EXPECT_DOUBLE_EQ(matcher.CoarsePsi(same), 1.0);
  for (const Alignment& off : {Alignment{{60.0, 60.0}, {63.0, 60.0}, 0.0}, Alignment{{60.0, 60.0}, {60.0, 60.0}, 0.1}}) {
    const double exact = matcher.Psi(off);
    EXPECT_LT(exact, 0.9);
    EXPECT_NEAR(matcher.CoarsePsi(off), exact, 0.1);
  }
}

TEST(PredictOptions, ThresholdOutsideThePapersRangeIsRejected) {
  PredictorOptions options;
  EXPECT_FALSE(ValidatePredictorOptions(options).has_value());
  options.similarity_threshold = 0.4;
  EXPECT_FALSE(ValidatePredictorOptions(options).has_value());
  options.similarity_threshold = 0.8;
  const auto error = ValidatePredictorOptions(options);
  ASSERT_TRUE(error.has_value());
  EXPECT_NE(error->find("similarity_threshold"), std::string::npos);
  EXPECT_THROW(StructurePredictor{options}, std::invalid_argument);
  options.similarity_threshold = 0.39;
  EXPECT_TRUE(ValidatePredictorOptions(options).has_value());
  options = {};
  options.max_reference_corners = 0;
  EXPECT_TRUE(ValidatePredictorOptions(options).has_value());
  options = {};
  options.coarse_rescored = -1;
  EXPECT_TRUE(ValidatePredictorOptions(options).has_value());
}

}  // namespace
}  // namespace pslam
