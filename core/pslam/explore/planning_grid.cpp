#include "pslam/explore/planning_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pslam/explore/distance_transform.hpp"

namespace pslam {

PlanningGrid::PlanningGrid(const OccupancyGrid& grid, const PlannerOptions& options)
    : options_(options), resolution_(grid.resolution()), box_(grid.KnownBounds()) {
  if (box_.empty()) return;
  // One cell of unknown margin, so every frontier of the known region lies inside the window.
  box_.min -= Eigen::Vector2i::Ones();
  box_.max += Eigen::Vector2i::Ones();
  const std::size_t n = static_cast<std::size_t>(box_.width()) * static_cast<std::size_t>(box_.height());
  classes_.resize(n);
  std::vector<bool> occupied(n);
  for (std::size_t i = 0; i < n; ++i) {
    classes_[i] = Classify(grid, CellAt(i), options_.classes);
    occupied[i] = classes_[i] == CellClass::kOccupied;
  }
  squared_clearance_cells_ = SquaredDistanceTransform(occupied, box_.width(), box_.height());

  const double inflation = options_.robot_radius + options_.inflation_margin;
  traversable_.resize(n);
  cost_factor_.assign(n, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const double clearance = std::sqrt(static_cast<double>(squared_clearance_cells_[i])) * resolution_;
    traversable_[i] = classes_[i] == CellClass::kFree && clearance >= inflation;
    if (options_.wall_cost_distance > 0.0) {
      const double closeness = std::clamp(1.0 - (clearance - inflation) / options_.wall_cost_distance, 0.0, 1.0);
      cost_factor_[i] = static_cast<float>(1.0 + options_.wall_cost_weight * closeness);
    }
  }
}

double PlanningGrid::Clearance(const Eigen::Vector2i& c) const {
  if (!Contains(c)) return std::numeric_limits<double>::infinity();
  return std::sqrt(static_cast<double>(squared_clearance_cells_[Index(c)])) * resolution_;
}

}  // namespace pslam
