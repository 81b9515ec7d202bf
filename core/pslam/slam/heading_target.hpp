#pragma once
// A recorded log has no exploration planner, so P-SLAM's target T_k (the next exploration goal)
// is inferred: the frontier cluster the robot is heading toward, i.e. the nearest cluster within
// a cone around its heading. This is what a planner would most likely have chosen next.
#include <Eigen/Core>
#include <optional>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/slam/pslam_options.hpp"

namespace pslam {

std::optional<Eigen::Vector2i> HeadingFrontierTarget(const OccupancyGrid& map, const Pose2D& robot,
                                                     const HeadingTargetOptions& options);

}  // namespace pslam
