#include "pslam/experiment/mapping_trajectory.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace pslam {
namespace {

constexpr double kBucket = 1.0;  // m

int BucketOf(double v) { return static_cast<int>(std::floor(v / kBucket)); }

}  // namespace

void SaveMappingTrajectory(const std::string& path, const std::vector<MappedPose>& poses) {
  std::ofstream out(path);
  out.precision(9);
  for (const MappedPose& p : poses) {
    out << p.truth.x << ' ' << p.truth.y << ' ' << p.truth.theta << ' ' << p.in_map.x << ' ' << p.in_map.y << ' '
        << p.in_map.theta << '\n';
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::vector<MappedPose> LoadMappingTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<MappedPose> poses;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    double v[6];
    for (double& x : v) fields >> x;
    if (!fields || !std::isfinite(v[0] + v[1] + v[2] + v[3] + v[4] + v[5])) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": expected six numbers");
    }
    poses.push_back({Pose2D(v[0], v[1], v[2]), Pose2D(v[3], v[4], v[5])});
  }
  return poses;
}

std::string MappingTrajectoryPath(const std::string& map_path) {
  const std::string suffix = ".yaml";
  const bool yaml = map_path.size() > suffix.size() && map_path.ends_with(suffix);
  return (yaml ? map_path.substr(0, map_path.size() - suffix.size()) : map_path) + "_trajectory.txt";
}

MapLocalFrame::MapLocalFrame(std::vector<MappedPose> poses) : poses_(std::move(poses)) {
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    buckets_[BucketKey(BucketOf(poses_[i].truth.x), BucketOf(poses_[i].truth.y))].push_back(i);
  }
}

long long MapLocalFrame::BucketKey(int bx, int by) {
  return (static_cast<long long>(bx) << 32) ^ static_cast<long long>(static_cast<unsigned>(by));
}

std::optional<Pose2D> MapLocalFrame::ToMap(const Pose2D& truth, double max_distance) const {
  const int reach = static_cast<int>(std::ceil(max_distance / kBucket));
  const int bx = BucketOf(truth.x), by = BucketOf(truth.y);
  double best = max_distance * max_distance;
  const MappedPose* nearest = nullptr;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const auto it = buckets_.find(BucketKey(bx + dx, by + dy));
      if (it == buckets_.end()) continue;
      for (const std::size_t i : it->second) {
        const double d2 = (poses_[i].truth.translation() - truth.translation()).squaredNorm();
        if (d2 <= best) best = d2, nearest = &poses_[i];
      }
    }
  }
  if (!nearest) return std::nullopt;
  return nearest->in_map * nearest->truth.inverse() * truth;
}

}  // namespace pslam
