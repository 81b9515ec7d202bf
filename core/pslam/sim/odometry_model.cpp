#include "pslam/sim/odometry_model.hpp"

#include <cmath>

#include "pslam/common/random.hpp"

namespace pslam {
namespace {

double Gaussian(std::mt19937_64& rng, double stddev) {
  return stddev > 0.0 ? std::normal_distribution<double>(0.0, stddev)(rng) : 0.0;
}

}  // namespace

DriftingOdometry::DriftingOdometry(const Pose2D& start, const OdometryNoiseOptions& options, std::uint64_t seed)
    : options_(options), rng_(MakeStream(seed, 0x0D0, 0)), pose_(start) {
  translation_scale_ = 1.0 + Gaussian(rng_, options_.translation_scale_error_stddev);
  rotation_scale_ = 1.0 + Gaussian(rng_, options_.rotation_scale_error_stddev);
}

const Pose2D& DriftingOdometry::Advance(const Pose2D& increment) {
  // A differential drive moves on arcs: the increment is a chord of signed length d, pointing at
  // half the turn dtheta, so (d, dtheta) with the midpoint heading below rebuild it exactly.
  const double d = std::copysign(std::hypot(increment.x, increment.y), increment.x);
  const double dtheta = increment.theta;
  if (d == 0.0 && dtheta == 0.0) return pose_;
  const double abs_d = std::abs(d), abs_dtheta = std::abs(dtheta);
  const double measured_d =
      d * translation_scale_ + Gaussian(rng_, options_.translation_stddev_per_sqrt_meter * std::sqrt(abs_d));
  const double rotation_variance =
      options_.rotation_stddev_per_sqrt_meter * options_.rotation_stddev_per_sqrt_meter * abs_d +
      options_.rotation_stddev_per_sqrt_radian * options_.rotation_stddev_per_sqrt_radian * abs_dtheta;
  const double measured_dtheta = dtheta * rotation_scale_ + Gaussian(rng_, std::sqrt(rotation_variance));
  const double heading = pose_.theta + measured_dtheta / 2.0;
  pose_ = Pose2D(pose_.x + measured_d * std::cos(heading), pose_.y + measured_d * std::sin(heading),
                 pose_.theta + measured_dtheta);
  return pose_;
}

}  // namespace pslam
