#pragma once
// Finding the way into space a prediction may have sealed off. Predicted cells are not verified: a
// predicted wall can stand where the building actually opens, and then a frontier seen through it
// (or behind it) is out of reach of the planner for good. Going on from the traversable space
// through predicted and unknown cells, at a higher cost per metre, finds the nearest such frontier
// and where the way to it leaves the traversable space: driving there shows whether it is open.
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <vector>

#include "pslam/explore/path_planner.hpp"
#include "pslam/explore/planning_grid.hpp"

namespace pslam {

struct WayInSearch {
  // Whether a cell may be passed through as unverified: predicted, or unknown, and not a wall the
  // robot itself has mapped (nor next to one).
  std::function<bool(const Eigen::Vector2i& cell)> unverified;
  // Cluster index (>= 0) of a planning-grid cell on a frontier worth reaching, -1 otherwise.
  std::function<int(std::size_t index)> wanted_cluster;
  // Traversable cells that may not be exits (near exits already tried, or under the robot).
  std::function<bool(const Eigen::Vector2i& cell)> excluded_exit;
  double cost_factor = 3.0;  // on the length of a step into an unverified cell
  // The search gives up beyond this cost (m): a way in that dear would not be taken.
  double max_cost = std::numeric_limits<double>::infinity();
};

struct WayIn {
  Eigen::Vector2i exit{0, 0};  // settled by 'tree': the robot can drive there
  int cluster = -1;
  double cost = 0.0;  // m, the tree's cost to the exit plus the way from there to the cluster
};

// Continues 'tree' from the settled cells that border unverified space. Cells the tree did not
// settle but that are traversable (free space behind the seal) cost their plain length. A tree
// stopped early has settled every cell up to some cost: give max_cost no more than that, or
// frontiers it merely did not get to pass for sealed off.
std::optional<WayIn> FindWayIn(const PlanningGrid& grid, const SearchTree& tree, const WayInSearch& search);

}  // namespace pslam
