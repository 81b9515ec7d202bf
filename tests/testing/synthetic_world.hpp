#pragma once
// Tiny synthetic worlds for tests: a room made of wall segments, and a laser that sees them.
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "pslam/sensor/laser_scan.hpp"

namespace pslam::testing {

struct Segment {
  Eigen::Vector2d a, b;
};

// A 10 m x 8 m room with a pillar and an alcove, so that every pose is distinguishable.
inline std::vector<Segment> RoomWalls() {
  auto box = [](double x0, double y0, double x1, double y1) {
    return std::vector<Segment>{{{x0, y0}, {x1, y0}}, {{x1, y0}, {x1, y1}}, {{x1, y1}, {x0, y1}}, {{x0, y1}, {x0, y0}}};
  };
  std::vector<Segment> walls = box(-5, -4, 5, 4);
  for (const auto& s : box(1.0, 0.5, 1.8, 1.3)) walls.push_back(s);
  walls.push_back({{-5, 1}, {-3.5, 1}});
  walls.push_back({{-3.5, 1}, {-3.5, 2.5}});
  walls.push_back({{2.5, -4}, {2.5, -2.2}});
  // Real walls do not sit on cell boundaries: shift the room off the 5 cm lattice.
  for (auto& w : walls) {
    w.a += Eigen::Vector2d(0.013, 0.021);
    w.b += Eigen::Vector2d(0.013, 0.021);
  }
  return walls;
}

// Another room, for scans that a map of RoomWalls() cannot explain (a robot carried off): smaller,
// 5.2 m x 3.9 m, with a box and a slanted wall where RoomWalls() has none.
inline std::vector<Segment> OtherRoomWalls() {
  std::vector<Segment> walls;
  auto box = [&](double x0, double y0, double x1, double y1) {
    walls.push_back({{x0, y0}, {x1, y0}});
    walls.push_back({{x1, y0}, {x1, y1}});
    walls.push_back({{x1, y1}, {x0, y1}});
    walls.push_back({{x0, y1}, {x0, y0}});
  };
  box(-2.3, -1.7, 2.9, 2.2);
  box(-0.9, -1.0, -0.4, -0.3);
  walls.push_back({{0.7, 2.2}, {1.9, 0.9}});
  return walls;
}

inline double RayHit(const Eigen::Vector2d& o, const Eigen::Vector2d& d, const std::vector<Segment>& walls) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& w : walls) {
    const Eigen::Vector2d e = w.b - w.a;
    const double denom = d.x() * e.y() - d.y() * e.x();
    if (std::abs(denom) < 1e-12) continue;
    const Eigen::Vector2d ao = w.a - o;
    const double t = (ao.x() * e.y() - ao.y() * e.x()) / denom;
    const double u = (ao.x() * d.y() - ao.y() * d.x()) / denom;
    if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
  }
  return best;
}

// A 181-beam, 180 degree scan taken from `pose` (sensor at the robot centre); odometry = `odom`.
inline LaserScan RenderScan(const Pose2D& pose, const std::vector<Segment>& walls, const Pose2D& odom,
                            double max_range = 20.0) {
  LaserScan scan;
  scan.angle_min = -std::numbers::pi / 2;
  scan.angle_increment = std::numbers::pi / 180.0;
  scan.max_range = max_range;
  scan.odometry = odom;
  for (int i = 0; i < 181; ++i) {
    const double a = pose.theta + scan.BeamAngle(static_cast<std::size_t>(i));
    const double r = RayHit(pose.translation(), {std::cos(a), std::sin(a)}, walls);
    scan.ranges.push_back(static_cast<float>(std::min(r, max_range)));
  }
  return scan;
}

}  // namespace pslam::testing
