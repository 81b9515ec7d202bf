#include "pslam/sensor/scan_points.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {

ScanPoints ToScanPoints(const LaserScan& scan, const ScanPointsOptions& options) {
  ScanPoints out;
  const Pose2D& mount = scan.sensor_offset;
  out.origin = Eigen::Vector2f(static_cast<float>(mount.x), static_cast<float>(mount.y));
  out.hits.reserve(scan.ranges.size());
  const double spacing2 = options.min_point_spacing * options.min_point_spacing;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double angle = scan.BeamAngle(i);
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    if (scan.IsReturn(i)) {
      const double r = scan.ranges[i];
      if (r > options.max_usable_range) {
        out.free_ends.push_back((mount * (dir * options.max_usable_range)).cast<float>());
        continue;
      }
      const Eigen::Vector2f p = (mount * (dir * r)).cast<float>();
      if (spacing2 > 0.0 && !out.hits.empty() && (p - out.hits.back()).squaredNorm() < spacing2) continue;
      out.hits.push_back(p);
    } else if (options.no_return_free_range > 0.0) {
      const float r = scan.ranges[i];
      // NaN and non-positive readings say nothing about free space; only "no echo" readings do.
      if (std::isfinite(r) ? r >= scan.max_range : std::isinf(r) && r > 0) {
        out.free_ends.push_back((mount * (dir * options.no_return_free_range)).cast<float>());
      }
    }
  }
  return out;
}

std::vector<Eigen::Vector2f> SelectEvenly(std::vector<Eigen::Vector2f> points, int max_count) {
  const std::size_t n = points.size(), m = static_cast<std::size_t>(std::max(0, max_count));
  if (n <= m) return points;
  std::vector<Eigen::Vector2f> out(m);
  for (std::size_t i = 0; i < m; ++i) out[i] = points[i * n / m];
  return out;
}

}  // namespace pslam
