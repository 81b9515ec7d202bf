#pragma once
// Odometry motion model (Thrun, Burgard, Fox, Probabilistic Robotics, 5.4): a relative motion is
// split into rotate, translate, rotate, and each part is perturbed with noise whose spread grows
// with the rotation and translation it comes with.
#include <random>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct MotionNoise {
  double rotation_per_rotation = 0.05;        // rad of heading noise per rad turned
  double rotation_per_translation = 0.02;     // rad per metre driven
  double translation_per_translation = 0.03;  // m per metre driven
  double translation_per_rotation = 0.01;     // m per rad turned
};

// Samples a noisy version of the relative motion `delta` (expressed in the robot frame).
Pose2D SampleMotion(const Pose2D& delta, const MotionNoise& noise, std::mt19937_64& rng);

}  // namespace pslam
