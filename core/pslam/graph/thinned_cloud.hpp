#pragma once
// A point cloud with at most one point per square cell of a given spacing, for correlative
// matching: where scans overlap, a cell's first point stands for it, so the cloud's size follows
// the area seen rather than the number of scans.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <vector>

namespace pslam {

class ThinnedCloud {
 public:
  explicit ThinnedCloud(double spacing) : spacing_(spacing) {}

  // Keeps p unless its cell already holds a point.
  void Add(const Eigen::Vector2d& p) {
    const auto kx = static_cast<std::int64_t>(std::floor(p.x() / spacing_));
    const auto ky = static_cast<std::int64_t>(std::floor(p.y() / spacing_));
    if (taken_.insert((kx << 32) ^ (ky & 0xffffffff)).second) points_.push_back(p.cast<float>());
  }

  const std::vector<Eigen::Vector2f>& points() const { return points_; }
  std::vector<Eigen::Vector2f> Take() { return std::move(points_); }

 private:
  double spacing_;
  std::unordered_set<std::int64_t> taken_;
  std::vector<Eigen::Vector2f> points_;
};

}  // namespace pslam
