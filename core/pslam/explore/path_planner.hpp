#pragma once
// Shortest paths on the planning grid: A* to one goal, or Dijkstra to every reachable cell (what
// the explorer needs to rank frontiers by path length with one search). 8-connected; diagonal steps
// may not cut the corner of an untraversable cell; each step costs its length times the wall cost
// of the cell entered. Searches stop after max_expanded_nodes and say so.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "pslam/explore/planning_grid.hpp"

namespace pslam {

class SearchTree;

// Called as each cell is settled, with its grid index and cost; returning false ends the search
// there (the cell counts as settled). Lets a caller stop once nothing farther can matter to it.
using SettleCallback = std::function<bool(std::size_t index, double cost)>;

// Dijkstra from 'start' over the whole reachable space when 'goal' is empty; A* that stops once
// 'goal' is settled otherwise. 'on_settle', when given, may end the search earlier.
// 'max_expanded_nodes', when given, replaces PlannerOptions::max_expanded_nodes.
SearchTree GrowSearchTree(const PlanningGrid& grid, const Eigen::Vector2d& start,
                          std::optional<Eigen::Vector2i> goal = std::nullopt, const SettleCallback& on_settle = {},
                          std::optional<std::size_t> max_expanded_nodes = std::nullopt);

// A search from one start position: best cost, path length and parent of every cell it settled.
// Keeps a pointer to the planning grid, which must outlive it.
class SearchTree {
 public:
  bool start_blocked() const { return start_blocked_; }  // no traversable cell within the escape radius
  bool truncated() const { return truncated_; }          // stopped at max_expanded_nodes
  bool stopped() const { return stopped_; }              // ended by the caller's SettleCallback
  std::size_t expanded_nodes() const { return expanded_; }

  bool Reached(const Eigen::Vector2i& c) const;
  double Cost(const Eigen::Vector2i& c) const;    // infinity when not reached
  double Length(const Eigen::Vector2i& c) const;  // m along the cell path; infinity when not reached
  // World waypoints from the start position to the centre of reached cell 'c', simplified by
  // line-of-sight shortcuts over traversable cells that keep at least the clearance of the cell
  // path they replace; empty when 'c' was not reached.
  std::vector<Eigen::Vector2d> PathTo(const Eigen::Vector2i& c) const;

 private:
  friend SearchTree GrowSearchTree(const PlanningGrid&, const Eigen::Vector2d&, std::optional<Eigen::Vector2i>,
                                   const SettleCallback&, std::optional<std::size_t>);
  explicit SearchTree(const PlanningGrid& grid) : grid_(&grid) {}

  const PlanningGrid* grid_;
  Eigen::Vector2d start_ = Eigen::Vector2d::Zero();
  bool start_blocked_ = false;
  bool truncated_ = false;
  bool stopped_ = false;
  std::size_t expanded_ = 0;
  std::vector<float> cost_;
  std::vector<float> length_;
  std::vector<std::int32_t> parent_;  // -1: a root (the start cell or an escape target)
  std::vector<bool> settled_;
};

enum class PlanStatus {
  kFound,
  kStartBlocked,     // no traversable cell within the start escape radius
  kGoalBlocked,      // the goal cell is not traversable (unknown, occupied or too close to a wall)
  kNoPath,           // the search ran out of reachable cells: the goal is walled off
  kNodeLimit,        // the search hit max_expanded_nodes first
};

struct PlannedPath {
  PlanStatus status = PlanStatus::kNoPath;
  std::vector<Eigen::Vector2d> waypoints;  // world coordinates: start, shortcuts, then goal exactly
  double length = 0.0;                     // m along the waypoints
  std::size_t expanded_nodes = 0;
};

PlannedPath PlanPath(const PlanningGrid& grid, const Eigen::Vector2d& start, const Eigen::Vector2d& goal);

// Length of a polyline.
double PolylineLength(const std::vector<Eigen::Vector2d>& points);

}  // namespace pslam
