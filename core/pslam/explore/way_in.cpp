#include "pslam/explore/way_in.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace pslam {

std::optional<WayIn> FindWayIn(const PlanningGrid& grid, const SearchTree& tree, const WayInSearch& search) {
  const std::size_t n = grid.size();
  const double res = grid.resolution();
  std::vector<float> cost(n, std::numeric_limits<float>::infinity());
  std::vector<std::int32_t> exit(n, -1);  // the settled cell each reached cell's way leaves from
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;

  const auto enterable = [&](const Eigen::Vector2i& c) {
    if (!grid.Contains(c) || tree.Reached(c)) return false;
    return grid.IsTraversable(c) || search.unverified(c);
  };
  // Seeds: settled cells with an enterable neighbour, at their own cost; none beyond max_cost,
  // where the search would stop anyway (it runs on every plan, the seeds' tests are its bulk).
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2i c = grid.CellAt(i);
    if (!tree.Reached(c) || tree.Cost(c) > search.max_cost) continue;
    if (search.excluded_exit && search.excluded_exit(c)) continue;
    bool border = false;
    for (int dy = -1; dy <= 1 && !border; ++dy) {
      for (int dx = -1; dx <= 1 && !border; ++dx)
        border = (dx != 0 || dy != 0) && enterable(c + Eigen::Vector2i(dx, dy));
    }
    if (!border) continue;
    cost[i] = static_cast<float>(tree.Cost(c));
    exit[i] = static_cast<std::int32_t>(i);
    open.push({cost[i], i});
  }
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > cost[i]) continue;  // stale
    if (d > search.max_cost) return std::nullopt;
    const Eigen::Vector2i c = grid.CellAt(i);
    const int cluster = search.wanted_cluster(i);
    if (cluster >= 0 && !tree.Reached(c)) return WayIn{grid.CellAt(static_cast<std::size_t>(exit[i])), cluster, d};
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const Eigen::Vector2i next = c + Eigen::Vector2i(dx, dy);
        if (!enterable(next)) continue;
        const std::size_t j = grid.Index(next);
        const double factor = grid.IsTraversable(next) ? 1.0 : search.cost_factor;
        const auto nd = static_cast<float>(d + ((dx != 0 && dy != 0) ? std::sqrt(2.0) : 1.0) * res * factor);
        if (nd >= cost[j]) continue;
        cost[j] = nd;
        exit[j] = exit[i];
        open.push({nd, j});
      }
    }
  }
  return std::nullopt;
}

}  // namespace pslam
