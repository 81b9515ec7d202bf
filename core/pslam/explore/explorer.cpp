#include "pslam/explore/explorer.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>
#include <unordered_set>

#include "pslam/grid/cell_key.hpp"

namespace pslam {
namespace {

// Whether an occupied cell of the map or a predicted wall lies within 'cells' (Chebyshev) of c;
// with 0, whether c itself is one.
bool NearWall(const OccupancyGrid& grid, const Eigen::Vector2i& c, int cells, const CellClassOptions& classes,
              const CoveredPredicate& predicted_wall) {
  for (int dy = -cells; dy <= cells; ++dy) {
    for (int dx = -cells; dx <= cells; ++dx) {
      const Eigen::Vector2i n = c + Eigen::Vector2i(dx, dy);
      if (Classify(grid, n, classes) == CellClass::kOccupied) return true;
      if (predicted_wall && predicted_wall(n)) return true;
    }
  }
  return false;
}

}  // namespace

std::optional<double> CoveredFraction(const OccupancyGrid& grid, const FrontierCluster& cluster,
                                      const ExploreRequest& request, double radius, int seal_cells,
                                      const CellClassOptions& classes) {
  // Multi-source Dijkstra (8-connected step lengths) from the cluster's cells into the unexplored
  // region behind them, out to 'radius': the space the robot would reveal by going there. Bounded
  // by the number of cells within the radius.
  const double max_cells = radius / grid.resolution();
  std::unordered_map<std::uint64_t, double> distance;
  using Entry = std::pair<double, Eigen::Vector2i>;
  const auto later = [](const Entry& a, const Entry& b) { return a.first > b.first; };
  std::priority_queue<Entry, std::vector<Entry>, decltype(later)> open(later);
  for (const auto& c : cluster.cells) open.push({0.0, c});
  std::unordered_set<std::uint64_t> sources;
  for (const auto& c : cluster.cells) sources.insert(CellKey(c));

  int unexplored = 0, hit = 0;
  while (!open.empty()) {
    const auto [d, c] = open.top();
    open.pop();
    const bool is_source = sources.count(CellKey(c)) > 0;
    if (!is_source) {
      const auto it = distance.find(CellKey(c));
      if (it != distance.end() && it->second < d) continue;  // stale
      // Reached cells are unknown to the explorer or predicted; one the grid knows and that is not
      // predicted (the merged map knows predicted cells) was observed and is still undecided.
      const bool predicted = request.predicted && request.predicted(c);
      const bool undecided = grid.IsKnown(c.x(), c.y()) && !predicted;
      if (!undecided) {
        ++unexplored;
        if (request.covered && request.covered(c)) ++hit;
      }
      // A predicted wall (or a cell next to a wall): the space behind is another's.
      if (NearWall(grid, c, seal_cells, classes, request.predicted_wall)) continue;
    }
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const Eigen::Vector2i n = c + Eigen::Vector2i(dx, dy);
        const double nd = d + ((dx != 0 && dy != 0) ? std::sqrt(2.0) : 1.0);
        if (nd > max_cells) continue;
        const bool unexplored_cell =
            Classify(grid, n, classes) == CellClass::kUnknown || (request.predicted && request.predicted(n));
        if (!unexplored_cell) continue;
        auto [it, inserted] = distance.try_emplace(CellKey(n), nd);
        if (!inserted) {
          if (it->second <= nd) continue;
          it->second = nd;
        }
        open.push({nd, n});
      }
    }
  }
  if (unexplored == 0) return std::nullopt;
  return static_cast<double>(hit) / unexplored;
}

ExploreDecision SelectNextTarget(const OccupancyGrid& grid, const ExploreRequest& request,
                                 const ExploreOptions& options) {
  ExploreDecision decision;
  const std::vector<FrontierCluster> clusters = FindFrontierClusters(grid, options.frontier);
  decision.clusters = static_cast<int>(clusters.size());
  if (clusters.empty()) return decision;

  const PlanningGrid planning(grid, options.planner);
  const SearchTree tree = GrowSearchTree(planning, request.robot_position);
  decision.start_blocked = tree.start_blocked();
  decision.search_truncated = tree.truncated();

  const FrontierCluster* best = nullptr;
  Eigen::Vector2i best_cell{0, 0};
  double best_length = std::numeric_limits<double>::infinity();
  for (const FrontierCluster& cluster : clusters) {
    // The representative: the reached cell nearest the centroid.
    const Eigen::Vector2i* representative = nullptr;
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& c : cluster.cells) {
      if (!tree.Reached(c)) continue;
      const double d = (grid.CellCenter(c) - cluster.centroid).squaredNorm();
      if (d < nearest) {
        nearest = d;
        representative = &c;
      }
    }
    if (representative == nullptr) {
      ++decision.unreachable;
      continue;
    }
    const Eigen::Vector2d position = grid.CellCenter(*representative);
    if (options.area && !options.area->contains(position)) {
      ++decision.outside_area;
      continue;
    }
    if ((position - request.robot_position).norm() < options.min_target_distance) {
      ++decision.too_close;
      continue;
    }
    bool blacklisted = false;
    for (const auto& b : request.blacklist) blacklisted = blacklisted || (b - position).norm() < options.blacklist_radius;
    if (blacklisted) {
      ++decision.blacklisted;
      continue;
    }
    if (options.mode == ExploreMode::kSkipPredicted && request.covered) {
      const auto fraction = CoveredFraction(grid, cluster, request, options.skip_radius, options.wall_seal_cells,
                                            options.frontier.classes);
      if (fraction && *fraction >= options.skip_covered_fraction) {
        ++decision.skipped;
        continue;
      }
    }
    const double length = tree.Length(*representative);
    if (length < best_length) {
      best_length = length;
      best = &cluster;
      best_cell = *representative;
    }
  }
  if (best == nullptr) return decision;

  ExploreTarget target;
  target.cluster = *best;
  target.cell = best_cell;
  target.position = grid.CellCenter(best_cell);
  target.path_length = best_length;
  target.path = tree.PathTo(best_cell);
  decision.target = std::move(target);
  return decision;
}

}  // namespace pslam
