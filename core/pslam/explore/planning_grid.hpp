#pragma once
// The built map as the path planner sees it: a dense window over the known cells with each cell's
// class and its clearance (distance to the nearest occupied cell). A cell is traversable when it is
// free and the robot's disc, plus a margin, fits there without touching an occupied cell.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

#include "pslam/explore/cell_class.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

struct PlannerOptions {
  CellClassOptions classes;
  double robot_radius = 0.25;        // m, the P3-DX's footprint
  double inflation_margin = 0.10;    // m added to the radius: map and control are not exact
  // Cost favouring distance from walls a little: a step right at the inflation edge costs
  // 1 + wall_cost_weight times its length, falling linearly to 1 at wall_cost_distance beyond it.
  double wall_cost_weight = 0.5;
  double wall_cost_distance = 0.5;   // m
  // A start cell that is not traversable (the robot's own cell is often still unknown: the laser
  // looks forward) is left along a straight, obstacle-free segment to a traversable cell within this.
  double start_escape_radius = 0.6;  // m
  // One search's bound: about the cells of a 35 m x 35 m map. Before exploration is called done,
  // the explorer searches past it (explorer.cpp).
  std::size_t max_expanded_nodes = 500000;
};

class PlanningGrid {
 public:
  PlanningGrid(const OccupancyGrid& grid, const PlannerOptions& options);

  double resolution() const { return resolution_; }
  int width() const { return box_.width(); }
  int height() const { return box_.height(); }
  std::size_t size() const { return classes_.size(); }

  bool Contains(const Eigen::Vector2i& c) const { return box_.Contains(c); }
  std::size_t Index(const Eigen::Vector2i& c) const { return box_.Index(c); }
  Eigen::Vector2i CellAt(std::size_t index) const {
    const auto w = static_cast<std::size_t>(box_.width());
    return {box_.min.x() + static_cast<int>(index % w), box_.min.y() + static_cast<int>(index / w)};
  }
  Eigen::Vector2i WorldToCell(const Eigen::Vector2d& p) const {
    return {static_cast<int>(std::floor(p.x() / resolution_)), static_cast<int>(std::floor(p.y() / resolution_))};
  }
  Eigen::Vector2d CellCenter(const Eigen::Vector2i& c) const {
    return {(c.x() + 0.5) * resolution_, (c.y() + 0.5) * resolution_};
  }

  // Cells outside the window are unknown, untraversable and far from obstacles.
  CellClass Class(const Eigen::Vector2i& c) const { return Contains(c) ? classes_[Index(c)] : CellClass::kUnknown; }
  double Clearance(const Eigen::Vector2i& c) const;  // m to the nearest occupied cell centre
  bool IsTraversable(const Eigen::Vector2i& c) const { return Contains(c) && traversable_[Index(c)]; }
  // Multiplier (>= 1) on the length of a step into a traversable cell: the wall cost.
  float CostFactor(std::size_t index) const { return cost_factor_[index]; }

  const PlannerOptions& options() const { return options_; }

 private:
  PlannerOptions options_;
  double resolution_;
  CellBox box_;
  std::vector<CellClass> classes_;
  std::vector<float> squared_clearance_cells_;
  std::vector<bool> traversable_;
  std::vector<float> cost_factor_;
};

}  // namespace pslam
