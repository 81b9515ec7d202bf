#include "pslam/explore/path_planner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

#include "pslam/grid/ray_caster.hpp"

namespace pslam {
namespace {

constexpr float kUnreached = std::numeric_limits<float>::infinity();
constexpr double kSqrt2 = 1.41421356237309515;

struct Move {
  int dx, dy;
  double length;  // in cells
};
constexpr std::array<Move, 8> kMoves = {{{1, 0, 1.0},
                                         {-1, 0, 1.0},
                                         {0, 1, 1.0},
                                         {0, -1, 1.0},
                                         {1, 1, kSqrt2},
                                         {1, -1, kSqrt2},
                                         {-1, 1, kSqrt2},
                                         {-1, -1, kSqrt2}}};

// Octile distance in metres: exact for an empty grid, never more than the true cost (factors >= 1).
double Heuristic(const Eigen::Vector2i& a, const Eigen::Vector2i& b, double resolution) {
  const int dx = std::abs(a.x() - b.x()), dy = std::abs(a.y() - b.y());
  return (std::max(dx, dy) + (kSqrt2 - 1.0) * std::min(dx, dy)) * resolution;
}

// Every cell on the straight segment a-b (both ends included) satisfies 'ok'.
template <typename Ok>
bool SegmentCells(const Eigen::Vector2i& a, const Eigen::Vector2i& b, Ok&& ok) {
  bool all = ok(b.x(), b.y());
  TraceRay(a, b, [&](int x, int y) { all = all && ok(x, y); });
  return all;
}

}  // namespace

bool SearchTree::Reached(const Eigen::Vector2i& c) const {
  // Only settled cells carry final costs; tentative ones are not reached.
  return grid_->Contains(c) && !settled_.empty() && settled_[grid_->Index(c)];
}

double SearchTree::Cost(const Eigen::Vector2i& c) const {
  return Reached(c) ? cost_[grid_->Index(c)] : std::numeric_limits<double>::infinity();
}

double SearchTree::Length(const Eigen::Vector2i& c) const {
  return Reached(c) ? length_[grid_->Index(c)] : std::numeric_limits<double>::infinity();
}

std::vector<Eigen::Vector2d> SearchTree::PathTo(const Eigen::Vector2i& c) const {
  if (!Reached(c)) return {};
  std::vector<Eigen::Vector2i> cells;
  for (auto i = static_cast<std::int32_t>(grid_->Index(c)); i >= 0; i = parent_[static_cast<std::size_t>(i)]) {
    cells.push_back(grid_->CellAt(static_cast<std::size_t>(i)));
  }
  std::reverse(cells.begin(), cells.end());

  // Greedy line-of-sight shortcuts: from each kept cell, jump to the last cell still visible. A
  // shortcut may not come closer to a wall than the stretch of cell path it replaces: the wall cost
  // kept that path off corners, and a straight line that grazes them would undo it (pure pursuit
  // cuts corners a little more still). The first cell is the start cell or the escape target, so
  // the segment from the start position to it is the one the search already accepted.
  std::vector<Eigen::Vector2d> path{start_};
  const bool start_in_root = grid_->WorldToCell(start_) == cells.front();
  if (!start_in_root) path.push_back(grid_->CellCenter(cells.front()));
  std::size_t i = 0;
  while (i + 1 < cells.size()) {
    std::size_t j = i + 1;
    double min_clearance = std::min(grid_->Clearance(cells[i]), grid_->Clearance(cells[j]));
    while (j + 1 < cells.size()) {
      const double next_min_clearance = std::min(min_clearance, grid_->Clearance(cells[j + 1]));
      const auto clear = [&](int x, int y) {
        return grid_->IsTraversable({x, y}) && grid_->Clearance({x, y}) >= next_min_clearance;
      };
      if (!SegmentCells(cells[i], cells[j + 1], clear)) break;
      min_clearance = next_min_clearance;
      ++j;
    }
    path.push_back(grid_->CellCenter(cells[j]));
    i = j;
  }
  return path;
}

SearchTree GrowSearchTree(const PlanningGrid& grid, const Eigen::Vector2d& start, std::optional<Eigen::Vector2i> goal,
                          const SettleCallback& on_settle, std::optional<std::size_t> max_expanded_nodes) {
  SearchTree tree(grid);
  tree.start_ = start;
  const std::size_t n = grid.size();
  tree.cost_.assign(n, kUnreached);
  tree.length_.assign(n, kUnreached);
  tree.parent_.assign(n, -1);
  tree.settled_.assign(n, false);
  const double res = grid.resolution();
  const PlannerOptions& options = grid.options();
  const std::size_t node_cap = max_expanded_nodes.value_or(options.max_expanded_nodes);

  using Entry = std::pair<double, std::size_t>;  // (cost + heuristic, index)
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const auto priority = [&](const Eigen::Vector2i& c, double cost) {
    return goal ? cost + Heuristic(c, *goal, res) : cost;
  };

  // Roots: the start cell if traversable, else every traversable cell within the escape radius
  // reachable in a straight line along which the robot gets no closer to walls than it is now (or
  // than its radius, if it is farther): a robot touching a desk corner must not escape along it.
  const Eigen::Vector2i start_cell = grid.WorldToCell(start);
  const auto add_root = [&](const Eigen::Vector2i& c, double length) {
    const std::size_t i = grid.Index(c);
    const double cost = length * grid.CostFactor(i);
    if (cost >= tree.cost_[i]) return;
    tree.cost_[i] = static_cast<float>(cost);
    tree.length_[i] = static_cast<float>(length);
    open.push({priority(c, cost), i});
  };
  if (grid.IsTraversable(start_cell)) {
    add_root(start_cell, 0.0);
  } else {
    const int reach = static_cast<int>(std::ceil(options.start_escape_radius / res));
    const double min_clearance = std::min(grid.Clearance(start_cell), options.robot_radius);
    const auto keeps_clear = [&](int x, int y) {
      return grid.Class({x, y}) != CellClass::kOccupied && grid.Clearance({x, y}) >= min_clearance;
    };
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        const Eigen::Vector2i c = start_cell + Eigen::Vector2i(dx, dy);
        const double distance = (grid.CellCenter(c) - start).norm();
        if (distance > options.start_escape_radius || !grid.IsTraversable(c)) continue;
        if (SegmentCells(start_cell, c, keeps_clear)) add_root(c, distance);
      }
    }
  }
  tree.start_blocked_ = open.empty();

  while (!open.empty()) {
    const auto [unused_priority, i] = open.top();
    open.pop();
    if (tree.settled_[i]) continue;  // a stale entry: the cell was settled at a lower cost
    if (tree.expanded_ >= node_cap) {
      tree.truncated_ = true;
      break;
    }
    tree.settled_[i] = true;
    ++tree.expanded_;
    const Eigen::Vector2i c = grid.CellAt(i);
    if (goal && c == *goal) break;
    if (on_settle && !on_settle(i, tree.cost_[i])) {
      tree.stopped_ = true;
      break;
    }
    for (const Move& m : kMoves) {
      const Eigen::Vector2i next = c + Eigen::Vector2i(m.dx, m.dy);
      if (!grid.IsTraversable(next)) continue;
      if (m.dx != 0 && m.dy != 0 &&
          (!grid.IsTraversable({c.x() + m.dx, c.y()}) || !grid.IsTraversable({c.x(), c.y() + m.dy}))) {
        continue;  // no cutting corners of untraversable cells
      }
      const std::size_t j = grid.Index(next);
      if (tree.settled_[j]) continue;
      const double step = m.length * res;
      const double cost = tree.cost_[i] + step * grid.CostFactor(j);
      if (cost >= tree.cost_[j]) continue;
      tree.cost_[j] = static_cast<float>(cost);
      tree.length_[j] = static_cast<float>(tree.length_[i] + step);
      tree.parent_[j] = static_cast<std::int32_t>(i);
      open.push({priority(next, cost), j});
    }
  }
  return tree;
}

PlannedPath PlanPath(const PlanningGrid& grid, const Eigen::Vector2d& start, const Eigen::Vector2d& goal) {
  PlannedPath result;
  const Eigen::Vector2i goal_cell = grid.WorldToCell(goal);
  if (!grid.IsTraversable(goal_cell)) {
    result.status = PlanStatus::kGoalBlocked;
    return result;
  }
  const SearchTree tree = GrowSearchTree(grid, start, goal_cell);
  result.expanded_nodes = tree.expanded_nodes();
  if (tree.start_blocked()) {
    result.status = PlanStatus::kStartBlocked;
  } else if (!tree.Reached(goal_cell)) {
    result.status = tree.truncated() ? PlanStatus::kNodeLimit : PlanStatus::kNoPath;
  } else {
    result.status = PlanStatus::kFound;
    result.waypoints = tree.PathTo(goal_cell);
    if (result.waypoints.size() >= 2) {
      result.waypoints.back() = goal;  // the goal itself, not its cell centre
    } else {
      result.waypoints.push_back(goal);  // start and goal in the same cell
    }
    result.length = PolylineLength(result.waypoints);
  }
  return result;
}

double PolylineLength(const std::vector<Eigen::Vector2d>& points) {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

}  // namespace pslam
