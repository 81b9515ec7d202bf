#include "pslam/common/pose2d.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace pslam {
namespace {

void ExpectPoseNear(const Pose2D& a, const Pose2D& b, double tol = 1e-9) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(NormalizeAngle(a.theta - b.theta), 0.0, tol);
}

TEST(Pose2D, NormalizeAngleIsInHalfOpenInterval) {
  EXPECT_NEAR(NormalizeAngle(3 * std::numbers::pi), std::numbers::pi, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-std::numbers::pi), std::numbers::pi, 1e-12);
  EXPECT_NEAR(NormalizeAngle(0.5 - 4 * std::numbers::pi), 0.5, 1e-12);
}

TEST(Pose2D, ComposeMovesInTheFirstFrame) {
  const Pose2D a(1.0, 2.0, std::numbers::pi / 2);
  const Pose2D b(1.0, 0.0, 0.0);
  ExpectPoseNear(a * b, Pose2D(1.0, 3.0, std::numbers::pi / 2));
  const Eigen::Vector2d p = a * Eigen::Vector2d(0.0, 1.0);
  EXPECT_NEAR(p.x(), 0.0, 1e-12);
  EXPECT_NEAR(p.y(), 2.0, 1e-12);
}

TEST(Pose2D, InverseAndBetweenUndoComposition) {
  const Pose2D a(0.3, -1.2, 2.9), b(-4.0, 0.5, -2.8);
  ExpectPoseNear(a * a.inverse(), Pose2D());
  ExpectPoseNear(a * Between(a, b), b);
  ExpectPoseNear(Between(a, b).inverse(), Between(b, a));
}

TEST(Pose2D, InterpolateTakesTheShortArc) {
  const Pose2D a(0, 0, 3.0), b(2, 4, -3.0);
  const Pose2D mid = Interpolate(a, b, 0.5);
  EXPECT_NEAR(mid.x, 1.0, 1e-12);
  EXPECT_NEAR(mid.y, 2.0, 1e-12);
  EXPECT_NEAR(std::abs(mid.theta), std::numbers::pi, 1e-9);
  ExpectPoseNear(Interpolate(a, b, 0.0), a);
  ExpectPoseNear(Interpolate(a, b, 1.0), b);
}

}  // namespace
}  // namespace pslam
