#pragma once
// Pure pursuit (Coulter, "Implementation of the pure pursuit path tracking algorithm", CMU-RI-TR-
// 92-01): steer along the circular arc through a point one lookahead distance ahead on the path.
// Two additions make it suit a differential drive that plans on a grid: it turns in place when
// that point is far off the heading (the start of a path, sharp corners), and it slows down for
// turns and for the goal, where it stops.
#include <Eigen/Core>
#include <cstddef>
#include <numbers>
#include <vector>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct DriveCommand {
  double linear = 0.0;   // m/s
  double angular = 0.0;  // rad/s
};

struct FollowerOptions {
  double lookahead_distance = 0.5;                              // m
  double max_linear_speed = 0.2;                                // m/s
  double max_angular_speed = 100.0 * std::numbers::pi / 180.0;  // rad/s
  double turn_in_place_angle = 45.0 * std::numbers::pi / 180.0; // rad: larger heading errors stop and turn
  double turn_gain = 1.5;                                       // rad/s per rad when turning in place
  double goal_tolerance = 0.15;                                 // m: reached when the centre is this close
  double goal_slowdown_distance = 0.5;                          // m: speed falls linearly inside this ...
  double min_approach_speed = 0.05;                             // m/s ... but not below this
};

struct FollowerOutput {
  DriveCommand command;
  bool goal_reached = false;
};

class PathFollower {
 public:
  explicit PathFollower(const FollowerOptions& options = {});

  // Replaces the path (world waypoints, the robot's position first or near it).
  void SetPath(std::vector<Eigen::Vector2d> path);
  const std::vector<Eigen::Vector2d>& path() const { return path_; }
  // A shorter lookahead follows the path more closely and cuts its corners less.
  void set_lookahead_distance(double metres) { options_.lookahead_distance = metres; }

  // The command for the robot at 'pose'. Progress along the path only moves forward, so a path
  // that doubles back is followed in order. No path, or the goal within tolerance: stop, reached.
  FollowerOutput Update(const Pose2D& pose);

 private:
  FollowerOptions options_;
  std::vector<Eigen::Vector2d> path_;
  std::size_t segment_ = 0;  // index of the path segment the robot is on (from path_[segment_])
};

}  // namespace pslam
