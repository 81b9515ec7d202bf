#include "pslam/sim/flood_fill.hpp"

namespace pslam {

std::size_t BoundsIndex(const World& world, const Eigen::Vector2i& c) {
  const CellBox& b = world.bounds();
  return static_cast<std::size_t>(c.y() - b.min.y()) * static_cast<std::size_t>(b.width()) +
         static_cast<std::size_t>(c.x() - b.min.x());
}

std::vector<bool> FloodFill4(const World& world, const Eigen::Vector2i& start,
                             const std::function<bool(const Eigen::Vector2i&)>& passable) {
  const CellBox& b = world.bounds();
  std::vector<bool> seen(static_cast<std::size_t>(b.width()) * static_cast<std::size_t>(b.height()));
  std::vector<Eigen::Vector2i> stack;
  const auto visit = [&](const Eigen::Vector2i& c) {
    if (!world.Contains(c) || seen[BoundsIndex(world, c)] || !passable(c)) return;
    seen[BoundsIndex(world, c)] = true;
    stack.push_back(c);
  };
  visit(start);
  while (!stack.empty()) {
    const Eigen::Vector2i c = stack.back();
    stack.pop_back();
    for (const Eigen::Vector2i& d : {Eigen::Vector2i(1, 0), Eigen::Vector2i(-1, 0), Eigen::Vector2i(0, 1),
                                    Eigen::Vector2i(0, -1)}) {
      visit(c + d);
    }
  }
  return seen;
}

}  // namespace pslam
