#include "pslam/explore/frontier.hpp"

#include <algorithm>
#include <array>

namespace pslam {
namespace {

const std::array<Eigen::Vector2i, 4> kFourNeighbours = {{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}};

}  // namespace

std::vector<Eigen::Vector2i> FindFrontierCells(const OccupancyGrid& grid, const FrontierOptions& options) {
  std::vector<Eigen::Vector2i> cells;
  const CellBox box = grid.KnownBounds();
  if (box.empty()) return cells;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      const Eigen::Vector2i c(x, y);
      if (Classify(grid, c, options.classes) != CellClass::kFree) continue;
      for (const auto& d : kFourNeighbours) {
        if (Classify(grid, c + d, options.classes) == CellClass::kUnknown) {
          cells.push_back(c);
          break;
        }
      }
    }
  }
  return cells;
}

std::vector<FrontierCluster> FindFrontierClusters(const OccupancyGrid& grid, const FrontierOptions& options) {
  const std::vector<Eigen::Vector2i> frontier = FindFrontierCells(grid, options);
  std::vector<FrontierCluster> clusters;
  if (frontier.empty()) return clusters;

  // Frontier cells lie inside the known bounds: mark them in a dense window over it.
  const CellBox box = grid.KnownBounds();
  enum : unsigned char { kNone, kPending, kTaken };
  std::vector<unsigned char> mark(static_cast<std::size_t>(box.width()) * static_cast<std::size_t>(box.height()), kNone);
  for (const auto& c : frontier) mark[box.Index(c)] = kPending;

  std::vector<Eigen::Vector2i> stack;
  for (const auto& seed : frontier) {
    if (mark[box.Index(seed)] != kPending) continue;
    FrontierCluster cluster;
    mark[box.Index(seed)] = kTaken;
    stack.push_back(seed);
    while (!stack.empty()) {
      const Eigen::Vector2i c = stack.back();
      stack.pop_back();
      cluster.cells.push_back(c);
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const Eigen::Vector2i n = c + Eigen::Vector2i(dx, dy);
          if ((dx == 0 && dy == 0) || !box.Contains(n) || mark[box.Index(n)] != kPending) continue;
          mark[box.Index(n)] = kTaken;
          stack.push_back(n);
        }
      }
    }
    if (static_cast<int>(cluster.size()) < options.min_cluster_cells) continue;
    for (const auto& c : cluster.cells) cluster.centroid += grid.CellCenter(c);
    cluster.centroid /= static_cast<double>(cluster.size());
    clusters.push_back(std::move(cluster));
  }
  std::stable_sort(clusters.begin(), clusters.end(),
                   [](const FrontierCluster& a, const FrontierCluster& b) { return a.size() > b.size(); });
  return clusters;
}

}  // namespace pslam
