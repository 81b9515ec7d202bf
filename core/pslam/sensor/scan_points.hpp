#pragma once
// A laser scan turned into points in the robot frame, once per scan, so that every particle can
// reuse them: hits (endpoints of returns) and free-space ends (beams without a usable return).
#include <Eigen/Core>
#include <vector>

#include "pslam/sensor/laser_scan.hpp"

namespace pslam {

struct ScanPointsOptions {
  double max_usable_range = 20.0;      // returns beyond this only carve free space, up to this range
  double no_return_free_range = 0.0;   // free space carved along beams with no return (0: none)
  double min_point_spacing = 0.0;      // drop hits closer than this to the previous kept hit
};

struct ScanPoints {
  Eigen::Vector2f origin{0.0f, 0.0f};        // sensor position in the robot frame
  std::vector<Eigen::Vector2f> hits;         // in the robot frame
  std::vector<Eigen::Vector2f> free_ends;    // in the robot frame: carve free space, mark nothing
};

ScanPoints ToScanPoints(const LaserScan& scan, const ScanPointsOptions& options);

// At most max_count of the points, evenly spread over them in their order.
std::vector<Eigen::Vector2f> SelectEvenly(std::vector<Eigen::Vector2f> points, int max_count);

}  // namespace pslam
