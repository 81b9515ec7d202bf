#include "pslam/explore/explorer.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>
#include <unordered_set>

#include "pslam/explore/way_in.hpp"
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

namespace {

// What going to a cluster is worth, in metres of path cost (ExploreOptions::gain_weight,
// keep_goal_bonus).
double Worth(const OccupancyGrid& grid, const FrontierCluster& cluster, const ExploreRequest& request,
             const ExploreOptions& options) {
  const double length = static_cast<double>(cluster.size()) * grid.resolution();
  double worth = options.gain_weight * std::min(length, options.gain_cap_m);
  if (request.current_goal) {
    const double r2 = options.keep_goal_radius * options.keep_goal_radius;
    for (const auto& c : cluster.cells) {
      if ((grid.CellCenter(c) - *request.current_goal).squaredNorm() <= r2) {
        worth += options.keep_goal_bonus;
        break;
      }
    }
  }
  return worth;
}

bool NearAny(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& p, double radius) {
  for (const auto& q : points) {
    if ((q - p).norm() < radius) return true;
  }
  return false;
}

}  // namespace

ExploreDecision SelectNextTarget(const OccupancyGrid& grid, const ExploreRequest& request,
                                 const ExploreOptions& options) {
  ExploreDecision decision;
  const std::vector<FrontierCluster> clusters = FindFrontierClusters(grid, options.frontier);
  decision.clusters = static_cast<int>(clusters.size());
  if (clusters.empty()) return decision;

  const PlanningGrid planning(grid, options.planner);
  std::vector<int> cluster_of(planning.size(), -1);
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    for (const auto& c : clusters[k].cells) {
      if (planning.Contains(c)) cluster_of[planning.Index(c)] = static_cast<int>(k);
    }
  }
  auto skipped = [&, cache = std::vector<int>(clusters.size(), -1)](std::size_t k) mutable {
    if (options.mode != ExploreMode::kSkipPredicted || !request.covered) return false;
    if (cache[k] < 0) {
      const auto fraction = CoveredFraction(grid, clusters[k], request, options.skip_radius, options.wall_seal_cells,
                                            options.frontier.classes);
      cache[k] = fraction && *fraction >= options.skip_covered_fraction ? 1 : 0;
    }
    return cache[k] == 1;
  };
  const auto left_out = [&](const Eigen::Vector2d& position) {
    return (options.area && !options.area->contains(position)) ||
           (position - request.robot_position).norm() < options.min_target_distance ||
           NearAny(request.blacklist, position, options.blacklist_radius);
  };
  std::vector<double> worth(clusters.size());
  for (std::size_t k = 0; k < clusters.size(); ++k) worth[k] = Worth(grid, clusters[k], request, options);
  const double max_worth = options.gain_weight * options.gain_cap_m + options.keep_goal_bonus;

  // Dijkstra settles cells in order of cost, so a cluster first reached at cost c is worth at most
  // c - max_worth: once that exceeds the best score so far, nothing farther can win. A cluster
  // counts toward the best score when the cell through which it was reached qualifies.
  double best_bound = std::numeric_limits<double>::infinity();
  std::vector<bool> seen(clusters.size(), false);
  const SettleCallback stop_when_settled = [&](std::size_t i, double cost) {
    if (cost - max_worth > best_bound) return false;
    const int k = cluster_of[i];
    if (k < 0 || seen[static_cast<std::size_t>(k)]) return true;
    seen[static_cast<std::size_t>(k)] = true;
    if (!left_out(planning.CellCenter(planning.CellAt(i))) && !skipped(static_cast<std::size_t>(k))) {
      best_bound = std::min(best_bound, cost - worth[static_cast<std::size_t>(k)]);
    }
    return true;
  };
  SearchTree tree = GrowSearchTree(planning, request.robot_position, std::nullopt, stop_when_settled);
  decision.start_blocked = tree.start_blocked();

  const ExploreDecision base = decision;
  const auto choose = [&](const SearchTree& t) {
    ExploreDecision d = base;
    d.search_truncated = t.truncated();
    d.expanded_nodes = t.expanded_nodes();
    std::size_t best = clusters.size();
    Eigen::Vector2i best_cell{0, 0};
    double best_score = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < clusters.size(); ++k) {
      const FrontierCluster& cluster = clusters[k];
      // The representative: the reached cell nearest the centroid; the cluster's cost: its cheapest
      // cell.
      const Eigen::Vector2i* representative = nullptr;
      double nearest = std::numeric_limits<double>::infinity();
      double entry_cost = std::numeric_limits<double>::infinity();
      for (const auto& c : cluster.cells) {
        if (!t.Reached(c)) continue;
        entry_cost = std::min(entry_cost, t.Cost(c));
        const double dd = (grid.CellCenter(c) - cluster.centroid).squaredNorm();
        if (dd < nearest) {
          nearest = dd;
          representative = &c;
        }
      }
      if (representative == nullptr) {
        ++(t.stopped() ? d.unranked : d.unreachable);
        continue;
      }
      const Eigen::Vector2d position = grid.CellCenter(*representative);
      if (options.area && !options.area->contains(position)) {
        ++d.outside_area;
        continue;
      }
      if ((position - request.robot_position).norm() < options.min_target_distance) {
        ++d.too_close;
        continue;
      }
      if (NearAny(request.blacklist, position, options.blacklist_radius)) {
        ++d.blacklisted;
        continue;
      }
      if (skipped(k)) {
        ++d.skipped;
        continue;
      }
      const double score = entry_cost - worth[k];
      if (score < best_score) {
        best_score = score;
        best = k;
        best_cell = *representative;
      }
    }
    if (best < clusters.size()) {
      ExploreTarget target;
      target.cluster = clusters[best];
      target.cell = best_cell;
      target.position = grid.CellCenter(best_cell);
      target.path_length = t.Length(best_cell);
      target.path = t.PathTo(best_cell);
      target.cost = best_score + worth[best];
      d.target = std::move(target);
    }
    return d;
  };
  decision = choose(tree);
  // The cell that set the bound qualified but its cluster's representative did not (too close,
  // blacklisted): rank everything.
  if (decision.done() && tree.stopped()) {
    tree = GrowSearchTree(planning, request.robot_position);
    decision = choose(tree);
  }
  // The node cap bounds one plan's time, not the map: a search it cut short has not shown that
  // the frontiers beyond are out of reach (the shipped office once ended its exploration
  // with 24 clusters left that way). Before calling the exploration done, search the whole map.
  if (decision.done() && tree.truncated()) {
    tree = GrowSearchTree(planning, request.robot_position, std::nullopt, {}, planning.size());
    decision = choose(tree);
  }
  if (options.way_in_cost_factor <= 0.0 || !request.predicted || tree.truncated()) return decision;

  // Way in: the nearest cluster that is not covered and that no traversable way reaches. While a
  // frontier is left to go to, only one way_in_premium times nearer (the search stops beyond): a
  // wing a predicted wall sealed off is entered as the robot passes it, not in a crossing of the
  // whole building once everything else is done, but a way in is a guess, the predicted wall most
  // often right, and no detour for a guess.
  std::vector<int> wanted(clusters.size(), -1);  // -1 unknown, 0 no, 1 yes
  WayInSearch search;
  search.cost_factor = options.way_in_cost_factor;
  if (decision.target) {
    search.max_cost = decision.target->cost / options.way_in_premium;
    // A tree stopped early settled every cell up to best_bound + max_worth, and no further.
    if (tree.stopped()) search.max_cost = std::min(search.max_cost, best_bound + max_worth);
  }
  search.unverified = [&](const Eigen::Vector2i& c) {
    const auto is_predicted = [&](const Eigen::Vector2i& n) {
      return request.predicted(n) || (request.predicted_wall && request.predicted_wall(n));
    };
    // Free cells the robot mapped but does not fit through are verified: too narrow, not sealed.
    if (planning.Class(c) != CellClass::kUnknown && !is_predicted(c)) return false;
    // Around an exit already reached the robot has looked: what is still unverified there stays so.
    if (NearAny(request.tried_way_ins, planning.CellCenter(c), options.way_in_tried_radius)) return false;
    const int seal = options.wall_seal_cells;
    for (int dy = -seal; dy <= seal; ++dy) {
      for (int dx = -seal; dx <= seal; ++dx) {
        const Eigen::Vector2i n = c + Eigen::Vector2i(dx, dy);
        if (planning.Class(n) == CellClass::kOccupied && !is_predicted(n)) return false;  // a mapped wall
      }
    }
    return true;
  };
  search.wanted_cluster = [&](std::size_t i) {
    const int k = cluster_of[i];
    if (k < 0) return -1;
    int& w = wanted[static_cast<std::size_t>(k)];
    if (w < 0) {
      const FrontierCluster& cluster = clusters[static_cast<std::size_t>(k)];
      w = !(options.area && !options.area->contains(cluster.centroid)) &&
                  !NearAny(request.blacklist, cluster.centroid, options.blacklist_radius) &&
                  !skipped(static_cast<std::size_t>(k))
              ? 1
              : 0;
    }
    return w == 1 ? k : -1;
  };
  search.excluded_exit = [&](const Eigen::Vector2i& c) {
    const Eigen::Vector2d p = planning.CellCenter(c);
    return (p - request.robot_position).norm() < options.min_target_distance ||
           NearAny(request.tried_way_ins, p, options.way_in_tried_radius) ||
           NearAny(request.blacklist, p, options.blacklist_radius);
  };
  const std::optional<WayIn> way_in = FindWayIn(planning, tree, search);
  if (!way_in) return decision;
  ExploreTarget target;
  target.cluster = clusters[static_cast<std::size_t>(way_in->cluster)];
  target.cell = way_in->exit;
  target.position = planning.CellCenter(way_in->exit);
  target.path_length = tree.Length(way_in->exit);
  target.path = tree.PathTo(way_in->exit);
  target.way_in = true;
  target.cost = way_in->cost;
  decision.target = std::move(target);
  return decision;
}

ExploreDecision SelectNextTargetOnMerged(const OccupancyGrid& merged, const OccupancyGrid& built,
                                         const ExploreRequest& request, const ExploreOptions& options) {
  ExploreDecision decision = SelectNextTarget(merged, request, options);
  if (decision.done() && decision.unreachable > 0) decision = SelectNextTarget(built, request, options);
  return decision;
}

}  // namespace pslam
