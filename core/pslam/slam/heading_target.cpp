#include "pslam/slam/heading_target.hpp"

#include <cmath>
#include <limits>

#include "pslam/explore/frontier.hpp"

namespace pslam {

std::optional<Eigen::Vector2i> HeadingFrontierTarget(const OccupancyGrid& map, const Pose2D& robot,
                                                     const HeadingTargetOptions& options) {
  std::optional<Eigen::Vector2i> best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const FrontierCluster& cluster : FindFrontierClusters(map)) {
    const Eigen::Vector2d to = cluster.centroid - robot.translation();
    const double distance = to.norm();
    const double bearing = NormalizeAngle(std::atan2(to.y(), to.x()) - robot.theta);
    if (distance > options.max_distance || std::abs(bearing) > options.max_bearing || distance >= best_distance) continue;
    best_distance = distance;
    // The cluster cell nearest its centroid stands for it (a centroid may lie off the frontier).
    double nearest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector2i& c : cluster.cells) {
      const double d = (map.CellCenter(c) - cluster.centroid).squaredNorm();
      if (d < nearest) {
        nearest = d;
        best = c;
      }
    }
  }
  return best;
}

}  // namespace pslam
