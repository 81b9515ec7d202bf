#pragma once
// The laser geometry the agent announces in `hello` (schema/ws/ingest.md).
#include <cstddef>

#include "pslam/common/pose2d.hpp"

namespace pslam::agent {

struct LaserDescription {
  double angle_min = 0.0;        // radians, first beam, sensor frame
  double angle_increment = 0.0;  // radians
  std::size_t beams = 0;
  double max_range = 0.0;        // metres
  double min_range = 0.0;
  Pose2D offset;                 // sensor pose in the robot frame
};

}  // namespace pslam::agent
