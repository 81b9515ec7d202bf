#include "pslam/explore/path_follower.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace pslam {
namespace {

// Parameter in [0, 1] of the point of segment a-b closest to p.
double Project(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  return len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
}

}  // namespace

PathFollower::PathFollower(const FollowerOptions& options) : options_(options) {}

void PathFollower::SetPath(std::vector<Eigen::Vector2d> path) {
  path_ = std::move(path);
  segment_ = 0;
}

FollowerOutput PathFollower::Update(const Pose2D& pose) {
  FollowerOutput out;
  const Eigen::Vector2d position = pose.translation();
  if (path_.empty() || (path_.back() - position).norm() <= options_.goal_tolerance) {
    out.goal_reached = true;
    return out;
  }
  if (path_.size() == 1) path_.insert(path_.begin(), position);  // a lone goal: head straight for it

  // Advance to the nearest segment among the current one and the next two: forward only, and
  // local, so a path passing near itself does not make the robot skip ahead.
  double t = 0.0, best = std::numeric_limits<double>::infinity();
  const std::size_t last = std::min(segment_ + 2, path_.size() - 2);
  for (std::size_t s = segment_; s <= last; ++s) {
    const double u = Project(path_[s], path_[s + 1], position);
    const double d = (path_[s] + u * (path_[s + 1] - path_[s]) - position).norm();
    if (d < best) {
      best = d;
      segment_ = s;
      t = u;
    }
  }

  // The lookahead point: lookahead_distance further along the path from the closest point.
  Eigen::Vector2d target = path_.back();
  double remaining = options_.lookahead_distance;
  Eigen::Vector2d from = path_[segment_] + t * (path_[segment_ + 1] - path_[segment_]);
  for (std::size_t s = segment_; s + 1 < path_.size(); ++s) {
    const double len = (path_[s + 1] - from).norm();
    if (len >= remaining) {
      target = from + remaining / len * (path_[s + 1] - from);
      break;
    }
    remaining -= len;
    from = path_[s + 1];
  }

  const Eigen::Vector2d to_target = target - position;
  const double alpha = NormalizeAngle(std::atan2(to_target.y(), to_target.x()) - pose.theta);
  if (std::abs(alpha) > options_.turn_in_place_angle) {
    out.command.angular = std::clamp(options_.turn_gain * alpha, -options_.max_angular_speed, options_.max_angular_speed);
    return out;
  }
  // Slow for turns (to zero at the turn-in-place angle, so the two regimes meet) and for the goal.
  const double goal_distance = (path_.back() - position).norm();
  double v = options_.max_linear_speed * (1.0 - std::abs(alpha) / options_.turn_in_place_angle);
  if (options_.goal_slowdown_distance > 0.0) {
    v = std::min(v, std::max(options_.max_linear_speed * goal_distance / options_.goal_slowdown_distance,
                             options_.min_approach_speed));
  }
  // Pure pursuit: the arc through the target has curvature 2 sin(alpha) / distance.
  const double curvature = 2.0 * std::sin(alpha) / std::max(to_target.norm(), 1e-6);
  double w = v * curvature;
  if (std::abs(w) > options_.max_angular_speed) {  // keep the arc, lower the speed
    v *= options_.max_angular_speed / std::abs(w);
    w = std::copysign(options_.max_angular_speed, w);
  }
  out.command = {v, w};
  return out;
}

}  // namespace pslam
