#pragma once
// The server plans in its map frame; the agent tracks in its odometry frame. The target message
// carries the robot's map pose at planning time; with the robot's odometry pose at (about) the
// same time it fixes the map -> odometry transform: p_odom = odom * map^-1 * p_map.
#include <Eigen/Core>
#include <utility>
#include <vector>

#include "pslam/common/pose2d.hpp"

namespace pslam::agent {

std::vector<Eigen::Vector2d> MapPathToOdometry(const std::vector<std::pair<double, double>>& path_map,
                                               const Pose2D& robot_in_map, const Pose2D& robot_in_odometry);

}  // namespace pslam::agent
