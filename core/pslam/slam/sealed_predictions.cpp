#include "pslam/slam/sealed_predictions.hpp"

#include <cstdint>
#include <deque>

namespace pslam {
namespace {

enum Passage : std::uint8_t { kBlocked = 0, kOpen = 1, kReached = 2 };

}  // namespace

std::vector<HypothesisCell> TakeSealedOff(Hypothesis& h, const OccupancyGrid& map, const CellClassifier& classify,
                                          int wall_reach_cells) {
  CellBox box;
  for (const std::vector<HypothesisCell>* cells : {&h.cells, &h.undecided_cells}) {
    for (const HypothesisCell& c : *cells) box.Extend(c.cell);
  }
  if (box.empty()) return {};
  const int margin = wall_reach_cells + 1;  // observed floor just outside the prediction joins it too
  box.Extend(box.min - Eigen::Vector2i(margin, margin));
  box.Extend(box.max + Eigen::Vector2i(margin, margin));
  std::vector<std::uint8_t> passage(static_cast<std::size_t>(box.width()) * box.height(), kBlocked);
  std::deque<Eigen::Vector2i> queue;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      const CellState s = classify(map.At(x, y));
      if (s == CellState::kFree) {
        passage[box.Index({x, y})] = kReached;
        queue.push_back({x, y});
      } else if (s == CellState::kUncertain) {
        passage[box.Index({x, y})] = kOpen;
      }
    }
  }
  // Predictions decide over what the map has not (undecided cells are predicted too).
  for (const std::vector<HypothesisCell>* cells : {&h.cells, &h.undecided_cells}) {
    for (const HypothesisCell& c : *cells) passage[box.Index(c.cell)] = c.occupied ? kBlocked : kOpen;
  }
  static const Eigen::Vector2i kSteps[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  while (!queue.empty()) {
    const Eigen::Vector2i c = queue.front();
    queue.pop_front();
    for (const Eigen::Vector2i& step : kSteps) {
      const Eigen::Vector2i n = c + step;
      if (!box.Contains(n)) continue;
      std::uint8_t& p = passage[box.Index(n)];
      if (p != kOpen) continue;
      p = kReached;
      queue.push_back(n);
    }
  }

  const auto joined = [&](const HypothesisCell& c) {
    if (!c.occupied) return passage[box.Index(c.cell)] == kReached;
    for (int dy = -wall_reach_cells; dy <= wall_reach_cells; ++dy) {
      for (int dx = -wall_reach_cells; dx <= wall_reach_cells; ++dx) {
        const Eigen::Vector2i n = c.cell + Eigen::Vector2i(dx, dy);
        if (box.Contains(n) && passage[box.Index(n)] == kReached) return true;
      }
    }
    return false;
  };
  return TakeCellsUnless(h, joined);
}

}  // namespace pslam
