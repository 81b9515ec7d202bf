#include "pslam/predict/features.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pslam/common/pose2d.hpp"

namespace pslam {
namespace {

constexpr double kResolution = 0.05;
constexpr double kDeg = std::numbers::pi / 180.0;

// Draws a wall of the given thickness (cells) from 'a' to 'b' (cell coordinates).
void DrawWall(CellRaster& r, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double thickness = 1.0) {
  const double length = (b - a).norm();
  const Eigen::Vector2d u = (b - a) / length;
  for (int y = 0; y < r.height; ++y) {
    for (int x = 0; x < r.width; ++x) {
      const Eigen::Vector2d p(x, y);
      const double t = (p - a).dot(u);
      const double off = std::abs((p - a).x() * u.y() - (p - a).y() * u.x());
      if (t >= -0.5 && t <= length + 0.5 && off <= thickness / 2.0) r.Local(x, y) = CellState::kOccupied;
    }
  }
}

// Angles of a corner's two arms, sorted, in degrees in [0, 360).
std::pair<double, double> ArmDegrees(const Corner& c) {
  auto deg = [](double a) { return std::fmod(a / kDeg + 360.0, 360.0); };
  const double a = deg(c.phi1), b = deg(c.phi2);
  return {std::min(a, b), std::max(a, b)};
}

double AngularError(double a_deg, double b_deg) { return std::abs(NormalizeAngle((a_deg - b_deg) * kDeg)) / kDeg; }

TEST(PredictFeatures, LShapedCornerHasArmsAlongBothWalls) {
  CellRaster raster({100, -40}, 120, 120, CellState::kFree);  // an origin off zero: positions are grid cells
  DrawWall(raster, {20, 20}, {100, 20});
  DrawWall(raster, {20, 20}, {20, 100});
  const MapFeatures features = ExtractFeatures(raster, kResolution);
  ASSERT_FALSE(features.lines.empty());
  int two_armed = 0;
  for (const Corner& c : features.corners) {
    if (c.arms != 2) continue;  // wall ends are one-armed corners
    ++two_armed;
    EXPECT_NEAR((c.position - Eigen::Vector2d(120, -20)).norm(), 0.0, 1.5);
    const auto [a, b] = ArmDegrees(c);
    EXPECT_LT(AngularError(a, 0.0), 3.0) << a;
    EXPECT_LT(AngularError(b, 90.0), 3.0) << b;
  }
  EXPECT_EQ(two_armed, 1);
  // The junction is the strongest corner of the image.
  ASSERT_FALSE(features.corners.empty());
  EXPECT_EQ(features.corners.front().arms, 2);
}

TEST(PredictFeatures, ObliqueThickCornerAnglesAreAccurate) {
  // Walls two cells thick at 30 and 120 degrees: the Hough segments of thick walls lean, and
  // the refit has to bring the angles back within a few degrees.
  CellRaster raster({0, 0}, 160, 160, CellState::kFree);
  const Eigen::Vector2d corner(50, 40);
  const Eigen::Vector2d u1(std::cos(30 * kDeg), std::sin(30 * kDeg)), u2(std::cos(120 * kDeg), std::sin(120 * kDeg));
  DrawWall(raster, corner, corner + 90.0 * u1, 2.0);
  DrawWall(raster, corner, corner + 90.0 * u2, 2.0);
  const MapFeatures features = ExtractFeatures(raster, kResolution);
  const Corner* found = nullptr;
  for (const Corner& c : features.corners) {
    if (c.arms == 2 && (c.position - corner).norm() < 3.0) found = &c;
  }
  ASSERT_NE(found, nullptr);
  const auto [a, b] = ArmDegrees(*found);
  EXPECT_LT(AngularError(a, 30.0), 3.0) << a;
  EXPECT_LT(AngularError(b, 120.0), 3.0) << b;
}

TEST(PredictFeatures, StraightWallEndIsOneArmedWithPerpendicular) {
  CellRaster raster({0, 0}, 100, 60, CellState::kFree);
  DrawWall(raster, {10, 30}, {90, 30});
  const MapFeatures features = ExtractFeatures(raster, kResolution);
  ASSERT_FALSE(features.corners.empty());
  for (const Corner& c : features.corners) {
    EXPECT_EQ(c.arms, 1);
    EXPECT_NEAR(std::abs(NormalizeAngle(c.phi2 - c.phi1)), std::numbers::pi / 2, 1e-9);
  }
}

TEST(PredictFeatures, NoStructureNoFeatures) {
  const MapFeatures features = ExtractFeatures(CellRaster({0, 0}, 80, 80, CellState::kFree), kResolution);
  EXPECT_TRUE(features.corners.empty());
  EXPECT_TRUE(features.lines.empty());
  EXPECT_TRUE(ExtractFeatures(CellRaster(), kResolution).corners.empty());
}

}  // namespace
}  // namespace pslam
