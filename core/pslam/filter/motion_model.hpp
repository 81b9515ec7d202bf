#pragma once
// Odometry motion model (Thrun, Burgard, Fox, Probabilistic Robotics, 5.4): a relative motion is
// split into rotate, translate, rotate, and each part is perturbed with noise whose spread grows
// with the rotation and translation it comes with.
#include <random>

#include "pslam/common/pose2d.hpp"

namespace pslam {

// Defaults are for motion already stabilised by scan matching (see Rbpf), which is far more
// accurate than raw wheel odometry; on the Intel log, larger noise mostly adds error that the
// weights then fail to undo.
struct MotionNoise {
  double rotation_per_rotation = 0.015;       // rad of heading noise per rad turned
  double rotation_per_translation = 0.006;    // rad per metre driven
  double translation_per_translation = 0.01;  // m per metre driven
  double translation_per_rotation = 0.003;    // m per rad turned
};

// Samples a noisy version of the relative motion `delta` (expressed in the robot frame).
Pose2D SampleMotion(const Pose2D& delta, const MotionNoise& noise, std::mt19937_64& rng);

}  // namespace pslam
