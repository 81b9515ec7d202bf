#include "pslam/slam/local_refutation.hpp"

#include <algorithm>
#include <unordered_set>

#include "pslam/grid/cell_key.hpp"

namespace pslam {
namespace {

template <typename IsWall>
bool AnyWithin(const Eigen::Vector2i& c, int tolerance, const IsWall& is_wall) {
  for (int dy = -tolerance; dy <= tolerance; ++dy) {
    for (int dx = -tolerance; dx <= tolerance; ++dx) {
      if (is_wall(c + Eigen::Vector2i(dx, dy))) return true;
    }
  }
  return false;
}

}  // namespace

std::vector<Eigen::Vector2i> FindContradictions(const std::vector<HypothesisCell>& seen, const Hypothesis& original,
                                                const OccupancyGrid& map, const CellClassifier& classify,
                                                int tolerance_cells) {
  const auto observed_wall = [&](const Eigen::Vector2i& c) { return classify(map.At(c.x(), c.y())) == CellState::kOccupied; };
  std::vector<Eigen::Vector2i> out;
  std::vector<Eigen::Vector2i> walls_where_floor_was_predicted;
  for (const HypothesisCell& c : seen) {
    const CellState state = classify(map.At(c.cell.x(), c.cell.y()));
    if (!c.occupied && state == CellState::kOccupied) walls_where_floor_was_predicted.push_back(c.cell);
    if (c.occupied && state == CellState::kFree && !AnyWithin(c.cell, tolerance_cells, observed_wall)) {
      out.push_back(c.cell);
    }
  }
  if (walls_where_floor_was_predicted.empty()) return out;
  std::unordered_set<std::uint64_t> predicted_walls;
  for (const HypothesisCell& c : original.cells) {
    if (c.occupied) predicted_walls.insert(CellKey(c.cell));
  }
  const auto predicted_wall = [&](const Eigen::Vector2i& c) { return predicted_walls.count(CellKey(c)) > 0; };
  for (const Eigen::Vector2i& c : walls_where_floor_was_predicted) {
    if (!AnyWithin(c, tolerance_cells, predicted_wall)) out.push_back(c);
  }
  return out;
}

std::vector<HypothesisCell> TakeNear(Hypothesis& h, const std::vector<Eigen::Vector2i>& points, double radius_cells) {
  if (points.empty() || radius_cells <= 0.0) return {};
  const double r2 = radius_cells * radius_cells;
  const auto far = [&](const HypothesisCell& c) {
    return std::none_of(points.begin(), points.end(),
                        [&](const Eigen::Vector2i& p) { return (c.cell - p).cast<double>().squaredNorm() <= r2; });
  };
  return TakeCellsUnless(h, far);
}

}  // namespace pslam
