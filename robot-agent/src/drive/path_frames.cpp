#include "drive/path_frames.hpp"

namespace pslam::agent {

std::vector<Eigen::Vector2d> MapPathToOdometry(const std::vector<std::pair<double, double>>& path_map,
                                               const Pose2D& robot_in_map, const Pose2D& robot_in_odometry) {
  const Pose2D odom_from_map = robot_in_odometry * robot_in_map.inverse();
  std::vector<Eigen::Vector2d> out;
  out.reserve(path_map.size());
  for (const auto& [x, y] : path_map) out.push_back(odom_from_map * Eigen::Vector2d(x, y));
  return out;
}

}  // namespace pslam::agent
