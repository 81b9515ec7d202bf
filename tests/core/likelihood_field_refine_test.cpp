// Refining a pose on the likelihood field: a scan's pose found from a few centimetres off,
// endpoints settling on the face of a wall that the beams saw however thick the wall is on the
// map, and a prior holding the pose where it is told to.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "pslam/io/map_io.hpp"
#include "pslam/localize/likelihood_field.hpp"
#include "pslam/sim/ray_cast.hpp"
#include "pslam/sim/world.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// A 5 m x 4 m room whose walls are 4 cells (0.2 m) thick, as walls of a map built from real
// scans often are; its inside spans 0.2..5.2 m by 0.2..4.2 m.
OccupancyGrid ThickWalledRoom() {
  OccupancyGrid grid(0.05);
  for (int y = 0; y < 88; ++y) {
    for (int x = 0; x < 108; ++x) {
      const bool inside = x >= 4 && x < 104 && y >= 4 && y < 84;
      grid.AddLogOdds(x, y, inside ? -4000 : 4000, -4000, 4000);
    }
  }
  return grid;
}

// The endpoints (robot frame) of a full turn of beams from 'pose'.
std::vector<Eigen::Vector2f> ScanFrom(const World& world, const Pose2D& pose) {
  std::vector<Eigen::Vector2f> points;
  for (int i = 0; i < 360; ++i) {
    const double a = i * kDegree;
    const double range = CastRay(world, pose.translation(), pose.theta + a, 20.0);
    if (range < 20.0) points.emplace_back(static_cast<float>(range * std::cos(a)), static_cast<float>(range * std::sin(a)));
  }
  return points;
}

TEST(LikelihoodFieldRefineTest, EndpointsSettleOnTheSeenFaceOfAThickWall) {
  const OccupancyGrid grid = ThickWalledRoom();
  const LikelihoodField field(grid, LikelihoodFieldOptions{});
  const Pose2D truth(2.0, 1.7, 0.3);
  const std::vector<Eigen::Vector2f> points = ScanFrom(World::FromGrid(grid), truth);
  ASSERT_GT(points.size(), 300u);
  // Inside the wall every cell centre scores alike; only the cell in front of an endpoint, toward
  // the robot, tells the face it saw from the cells behind it.
  const Pose2D off(truth.x + 0.06, truth.y - 0.04, truth.theta + 1.5 * kDegree);
  const Pose2D refined = field.Refine(points, off, 0.12, 0.1);
  EXPECT_LT((refined.translation() - truth.translation()).norm(), 0.02);  // 3 cm without the check
  EXPECT_LT(std::abs(NormalizeAngle(refined.theta - truth.theta)), 0.3 * kDegree);
  // An endpoint in the wall's outermost cell scores as a miss when seen from inside the room, but
  // as on the wall when seen from outside, where that cell is the face.
  const Eigen::Vector2d behind(0.025, 2.0);
  EXPECT_FLOAT_EQ(field.SeenLogLikelihood(behind, {2.0, 2.0}), field.miss_log_likelihood());
  EXPECT_GT(field.SeenLogLikelihood(behind, {-3.0, 2.0}), field.miss_log_likelihood() + 1.0);
}

TEST(LikelihoodFieldRefineTest, FindsThePoseOfAScanInTheIrregularRoom) {
  // Endpoints on the shipped room's walls, seen from its start pose; a fit from 6 cm and 2 degrees
  // off comes back to within a cell, and never leaves the bounds it was given.
  std::string yaml = PSLAM_SOURCE_DIR;
  yaml.append("/core/worlds/irregular.yaml");
  const OccupancyGrid map = LoadMap(yaml);
  const LikelihoodField field(map, LikelihoodFieldOptions{});
  const Pose2D truth = ReadStartPose(yaml).value();
  const std::vector<Eigen::Vector2f> points = ScanFrom(World::FromGrid(map), truth);
  ASSERT_GT(points.size(), 100u);
  const Pose2D off(truth.x + 0.05, truth.y - 0.035, truth.theta + 2.0 * kDegree);
  const Pose2D refined = field.Refine(points, off, 0.12, 0.1);
  EXPECT_LT((refined.translation() - truth.translation()).norm(), 0.04);
  EXPECT_LT(std::abs(NormalizeAngle(refined.theta - truth.theta)), 0.5 * kDegree);
  const Pose2D bounded = field.Refine(points, off, 0.01, 0.005);
  EXPECT_LE((bounded.translation() - off.translation()).norm(), 0.01 + 1e-9);
}

TEST(LikelihoodFieldRefineTest, APriorHoldsThePoseInProportionToItsInformation) {
  const OccupancyGrid grid = ThickWalledRoom();
  const LikelihoodField field(grid, LikelihoodFieldOptions{});
  const Pose2D truth(3.0, 2.5, -0.4);
  const std::vector<Eigen::Vector2f> points = ScanFrom(World::FromGrid(grid), truth);
  const Pose2D off(truth.x + 0.06, truth.y + 0.03, truth.theta);
  const double free_error = (field.Refine(points, off, 0.12, 0.1).translation() - truth.translation()).norm();
  EXPECT_LT(free_error, 0.02);

  RefinePrior loose;
  loose.position_information = Eigen::Matrix2d::Identity() / (0.03 * 0.03);
  loose.heading_information = 1.0 / (0.02 * 0.02);
  loose.likelihood_weight = 60.0 / (static_cast<double>(points.size()) * 5.0);  // as the localizer weighs it
  const Pose2D pulled = field.Refine(points, off, 0.12, 0.1, 0.002, loose);
  const double pulled_error = (pulled.translation() - truth.translation()).norm();
  EXPECT_GT(pulled_error, free_error);
  EXPECT_LT(pulled_error, 0.5 * (off.translation() - truth.translation()).norm());

  RefinePrior stiff = loose;
  stiff.position_information *= 1e6;
  stiff.heading_information *= 1e6;
  const Pose2D held = field.Refine(points, off, 0.12, 0.1, 0.002, stiff);
  EXPECT_LT((held.translation() - off.translation()).norm(), 0.003);
}

}  // namespace
}  // namespace pslam
