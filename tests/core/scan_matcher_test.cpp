#include "pslam/matching/scan_matcher.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "pslam/grid/scan_inserter.hpp"
#include "pslam/matching/scan_likelihood.hpp"
#include "testing/synthetic_world.hpp"

namespace pslam {
namespace {

class ScanMatcherTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ScanInserter inserter;
    // Map the room from a few poses so the walls are well established.
    for (const Pose2D& p : {Pose2D(0, 0, 0), Pose2D(-2, -1, 2.5), Pose2D(0.5, -2, -1.2), Pose2D(-1, 2, 1.0)}) {
      inserter.Insert(ToScanPoints(testing::RenderScan(p, walls_, p), {}), p, grid_);
    }
  }
  std::vector<testing::Segment> walls_ = testing::RoomWalls();
  OccupancyGrid grid_{0.05};
};

TEST_F(ScanMatcherTest, RecoversAKnownOffset) {
  const Pose2D truth(0.4, -0.3, 0.3);
  const ScanPoints points = ToScanPoints(testing::RenderScan(truth, walls_, truth), {});
  const Pose2D start = truth * Pose2D(0.12, -0.08, 0.06);  // 14 cm and 3.4 degrees off
  const ScanMatchResult result = MatchScan(grid_, points.hits, start, ScanMatchOptions{.coarsest_level = 2});
  ASSERT_TRUE(result.converged);
  EXPECT_NEAR(result.pose.x, truth.x, 0.02);
  EXPECT_NEAR(result.pose.y, truth.y, 0.02);
  EXPECT_NEAR(NormalizeAngle(result.pose.theta - truth.theta), 0.0, 0.01);
  EXPECT_GT(result.score, ScoreScan(grid_, points.hits, start));
}

TEST_F(ScanMatcherTest, FailsCleanlyOnAnEmptyMap) {
  const OccupancyGrid empty(0.05);
  const ScanPoints points = ToScanPoints(testing::RenderScan(Pose2D(), walls_, Pose2D()), {});
  const Pose2D start(1, 2, 0.3);
  const ScanMatchResult result = MatchScan(empty, points.hits, start, {});
  EXPECT_FALSE(result.converged);
  EXPECT_DOUBLE_EQ(result.pose.x, start.x);  // an untrusted match leaves the guess alone
}

TEST_F(ScanMatcherTest, LikelihoodPrefersTheTruePose) {
  const Pose2D truth(-0.5, 0.8, -0.4);
  const ScanPoints points = ToScanPoints(testing::RenderScan(truth, walls_, truth), {});
  const LikelihoodOptions options;
  const ScanLikelihood at_truth = ComputeScanLikelihood(grid_, points.hits, truth, options);
  const ScanLikelihood shifted = ComputeScanLikelihood(grid_, points.hits, truth * Pose2D(0.1, 0, 0.05), options);
  EXPECT_GT(at_truth.Total(false), shifted.Total(false));
  EXPECT_GT(at_truth.explored_points, 50);
  EXPECT_LE(at_truth.unexplored_points, 3);
}

// A 2.2 m corridor 80 m long, mapped from seven poses along its middle: an 8 m laser sees
// neither end.
struct Corridor {
  std::vector<testing::Segment> walls{{{-40, -1.1}, {40, -1.1}}, {{-40, 1.1}, {40, 1.1}}};
  OccupancyGrid grid{0.05};
  Corridor() {
    const ScanInserter inserter;
    for (double x = -3; x <= 3; x += 1.0) inserter.Insert(ScanAt(Pose2D(x, 0, 0)), Pose2D(x, 0, 0), grid);
  }
  ScanPoints ScanAt(const Pose2D& pose) const { return ToScanPoints(testing::RenderScan(pose, walls, pose, 8.0), {}); }
};

// In a corridor whose ends are out of the laser's reach, the scan says nothing along it. The
// degeneracy guard keeps the guess there (odometry holds it) and still corrects across.
TEST(ScanMatcherDegeneracyTest, ACorridorWithoutEndsKeepsTheGuessAlongItAndCorrectsAcross) {
  const Corridor corridor;
  const OccupancyGrid& grid = corridor.grid;
  const Pose2D truth(0.3, 0.2, 0.0);
  const ScanPoints points = corridor.ScanAt(truth);
  const Pose2D start(0.45, 0.1, 0.03);  // 15 cm behind along the corridor, 10 cm off across it
  ScanMatchOptions options{.coarsest_level = 2};
  options.degenerate_ratio = 0.15;
  const ScanMatchResult result = MatchScan(grid, points.hits, start, options);
  ASSERT_TRUE(result.converged);
  EXPECT_NEAR(result.pose.y, truth.y, 0.02);
  EXPECT_NEAR(result.pose.theta, truth.theta, 0.01);
  EXPECT_NEAR(result.pose.x, start.x, 0.01) << "slid along the corridor on nothing";
  const Eigen::Matrix2d translation = result.hessian.topLeftCorner<2, 2>();
  EXPECT_LT(translation(0, 0), 0.15 * translation(1, 1)) << "the corridor should be degenerate along x";
}

// The prior toward the guess is a weight against the map: without it the match goes to the truth,
// and the heavier it is the closer the result stays to the guess, between the two.
TEST_F(ScanMatcherTest, ThePriorHoldsTheGuessInProportionToItsWeight) {
  const Pose2D truth(0.4, -0.3, 0.3);
  const ScanPoints points = ToScanPoints(testing::RenderScan(truth, walls_, truth), {});
  const Pose2D start = truth * Pose2D(0.06, -0.04, 0.0);  // 7 cm off
  const auto distance_to = [](const Pose2D& a, const Pose2D& b) { return std::hypot(a.x - b.x, a.y - b.y); };
  double last_from_start = 1.0;
  for (const double weight : {0.0, 5.0, 30.0}) {
    ScanMatchOptions options{.coarsest_level = 1};
    options.prior_translation_weight = weight;
    const ScanMatchResult result = MatchScan(grid_, points.hits, start, options);
    ASSERT_TRUE(result.converged) << weight;
    const double from_start = distance_to(result.pose, start);
    if (weight == 0.0) EXPECT_LT(distance_to(result.pose, truth), 0.02);
    else EXPECT_LT(from_start, last_from_start) << "weight " << weight;
    EXPECT_LT(distance_to(result.pose, truth), distance_to(start, truth) + 1e-9) << "weight " << weight;
    last_from_start = from_start;
  }
  EXPECT_LT(last_from_start, 0.02) << "a heavy prior should all but keep the guess";
}

// Without the degeneracy guard, the prior alone keeps the guess along a corridor whose ends are out
// of reach, and the Hessian reported for the guard is still the scan's own.
TEST(ScanMatcherDegeneracyTest, ThePriorKeepsTheGuessAlongACorridorWithoutTheGuard) {
  const Corridor corridor;
  const OccupancyGrid& grid = corridor.grid;
  const Pose2D truth(0.3, 0.2, 0.0);
  const ScanPoints points = corridor.ScanAt(truth);
  const Pose2D start(0.45, 0.1, 0.0);
  ScanMatchOptions options{.coarsest_level = 2};
  options.prior_translation_weight = 5.0;
  const ScanMatchResult result = MatchScan(grid, points.hits, start, options);
  ASSERT_TRUE(result.converged);
  EXPECT_NEAR(result.pose.x, start.x, 0.01) << "slid along the corridor on nothing";
  EXPECT_LT(std::abs(result.pose.y - truth.y), std::abs(start.y - truth.y)) << "should correct across the corridor";
  const Eigen::Matrix2d translation = result.hessian.topLeftCorner<2, 2>();
  EXPECT_LT(translation(0, 0), 0.15 * translation(1, 1)) << "the reported Hessian should be the scan's alone";
}

// A beam cannot end inside a wall it had to cross first: with the free-space check an endpoint at
// the back of a thick wall scores worse than one on its face; without it both score as hits.
TEST(ScanLikelihoodTest, FreeSpaceCheckRejectsEndpointsBehindAWall) {
  OccupancyGrid grid(0.05);
  for (int cy = -10; cy <= 10; ++cy) {
    for (int cx = 0; cx < 20; ++cx) grid.MutableAt(cx, cy) = -2000;    // free in front of the wall
    for (int cx = 20; cx <= 22; ++cx) grid.MutableAt(cx, cy) = 3000;  // a wall three cells thick
  }
  const Pose2D robot;  // at the origin, looking along +x at the wall's face (x = 1.0 m)
  const std::vector<Eigen::Vector2f> on_face{grid.CellCenter({20, 0}).cast<float>()};
  const std::vector<Eigen::Vector2f> at_back{grid.CellCenter({22, 0}).cast<float>()};
  LikelihoodOptions checked;
  checked.point_step = 1;
  LikelihoodOptions unchecked = checked;
  unchecked.free_space_check = false;

  EXPECT_NEAR(ComputeScanLikelihood(grid, at_back, robot, unchecked).Total(false), 0.0, 1e-9);
  EXPECT_NEAR(ComputeScanLikelihood(grid, on_face, robot, checked).Total(false), 0.0, 1e-9);
  const ScanLikelihood behind = ComputeScanLikelihood(grid, at_back, robot, checked);
  EXPECT_EQ(behind.explored_points, 1);
  EXPECT_LT(behind.Total(false), -1.0);  // scored by the face, two cells away
}

}  // namespace
}  // namespace pslam
