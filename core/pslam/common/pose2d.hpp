#pragma once
// Rigid 2D transform (x, y, theta): the pose of a frame in its parent. Composition follows the
// usual SE(2) convention: (a * b) maps b's frame into a's parent, so a * b = "a, then b in a's frame".
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace pslam {

inline double NormalizeAngle(double a) {
  a = std::fmod(a + std::numbers::pi, 2.0 * std::numbers::pi);
  if (a <= 0.0) a += 2.0 * std::numbers::pi;
  return a - std::numbers::pi;  // in (-pi, pi]
}

struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  Pose2D() = default;
  Pose2D(double x_, double y_, double theta_) : x(x_), y(y_), theta(NormalizeAngle(theta_)) {}

  Eigen::Vector2d translation() const { return {x, y}; }
  Eigen::Matrix2d rotation() const { return Eigen::Rotation2Dd(theta).toRotationMatrix(); }

  Pose2D operator*(const Pose2D& other) const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {x + c * other.x - s * other.y, y + s * other.x + c * other.y, theta + other.theta};
  }
  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
  Pose2D inverse() const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {-c * x - s * y, s * x - c * y, -theta};
  }
};

// Relative motion from `from` to `to`, expressed in `from`'s frame: from^-1 * to.
inline Pose2D Between(const Pose2D& from, const Pose2D& to) { return from.inverse() * to; }

// Linear interpolation of translation and shortest-arc interpolation of heading; t in [0, 1].
inline Pose2D Interpolate(const Pose2D& a, const Pose2D& b, double t) {
  return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.theta + t * NormalizeAngle(b.theta - a.theta)};
}

}  // namespace pslam
