#pragma once
// Where a built map has each place. A map is bent where its filter erred, so a robot localized on
// it is right when it stands where the map has it, not where the world has it. Saved beside a map
// (PREFIX_trajectory.txt), the mapping run's true pose and the map's own pose at every scan (the
// best particle's corrected trajectory, from which the map was drawn) carry a true pose into the
// map as it is around that place: what localization on the map can be scored against apart from
// the map's own error.
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct MappedPose {
  Pose2D truth;   // world frame
  Pose2D in_map;  // the map's frame
};

// One line per pose: "truth_x truth_y truth_theta map_x map_y map_theta". Throws on write errors.
void SaveMappingTrajectory(const std::string& path, const std::vector<MappedPose>& poses);
// Throws std::runtime_error naming the file and line when it cannot be read or parsed.
std::vector<MappedPose> LoadMappingTrajectory(const std::string& path);
// PREFIX_trajectory.txt for the map PREFIX.yaml (or PREFIX).
std::string MappingTrajectoryPath(const std::string& map_path);

class MapLocalFrame {
 public:
  explicit MapLocalFrame(std::vector<MappedPose> poses);

  // 'truth' carried into the map by the mapping pose whose true position is nearest to it
  // (in_map * truth^-1 of that pose), or nothing when none lies within 'max_distance' metres.
  std::optional<Pose2D> ToMap(const Pose2D& truth, double max_distance = 1.0) const;

 private:
  static long long BucketKey(int bx, int by);

  std::vector<MappedPose> poses_;
  std::unordered_map<long long, std::vector<std::size_t>> buckets_;  // 1 m squares of true positions
};

}  // namespace pslam
