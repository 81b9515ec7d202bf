#include "pslam/filter/motion_model.hpp"

#include <cmath>

namespace pslam {

Pose2D SampleMotion(const Pose2D& delta, const MotionNoise& n, std::mt19937_64& rng) {
  const double trans = std::hypot(delta.x, delta.y);
  // Below a few millimetres the direction of travel is meaningless: treat it as a pure rotation.
  const double rot1 = trans < 1e-3 ? 0.0 : std::atan2(delta.y, delta.x);
  const double rot2 = NormalizeAngle(delta.theta - rot1);
  auto gauss = [&rng](double sigma) { return sigma > 0.0 ? std::normal_distribution<double>(0.0, sigma)(rng) : 0.0; };
  const double r1 = std::abs(NormalizeAngle(rot1)), r2 = std::abs(rot2);
  const double rot1_hat = rot1 + gauss(n.rotation_per_rotation * r1 + n.rotation_per_translation * trans);
  const double trans_hat = trans + gauss(n.translation_per_translation * trans + n.translation_per_rotation * (r1 + r2));
  const double rot2_hat = rot2 + gauss(n.rotation_per_rotation * r2 + n.rotation_per_translation * trans);
  return {trans_hat * std::cos(rot1_hat), trans_hat * std::sin(rot1_hat), rot1_hat + rot2_hat};
}

}  // namespace pslam
