#include "pslam/predict/region_matcher.hpp"

#include <cmath>
#include <cstdint>
#include <utility>

namespace pslam {
namespace {

// One cell in four, by a hash of its position: fixed, so that a prediction is reproducible.
bool InSample(int x, int y) {
  const auto h = static_cast<std::uint32_t>(x) * 73856093u ^ static_cast<std::uint32_t>(y) * 19349663u;
  return ((h ^ (h >> 13)) & 3u) == 0;
}

}  // namespace

MatchWindow MakeMatchWindow(const CellRaster& window, int tolerance_cells) {
  MatchWindow w{window.origin, window.width, window.height, {}};
  const std::vector<std::uint8_t> near = DilatedOccupancy(window, tolerance_cells);
  w.flags.resize(window.cells.size());
  for (std::size_t i = 0; i < w.flags.size(); ++i) {
    w.flags[i] = static_cast<std::uint8_t>((window.cells[i] == CellState::kOccupied ? MatchWindow::kOccupied : 0) |
                                           (near[i] ? MatchWindow::kNearOccupied : 0));
  }
  return w;
}

RegionMatcher::RegionMatcher(const CellRaster& window, const CellRaster& target, int tolerance_cells)
    : RegionMatcher(std::make_shared<const MatchWindow>(MakeMatchWindow(window, tolerance_cells)), target,
                    tolerance_cells) {}

RegionMatcher::RegionMatcher(std::shared_ptr<const MatchWindow> window, const CellRaster& target,
                             int tolerance_cells)
    : window_(std::move(window)), target_origin_(target.origin) {
  const std::vector<std::uint8_t> target_near = DilatedOccupancy(target, tolerance_cells);
  for (int y = 0; y < target.height; ++y) {
    for (int x = 0; x < target.width; ++x) {
      const CellState s = target.Local(x, y);
      if (!IsExplored(s)) continue;  // Psi is evaluated over the explored part of S_f only
      const std::size_t i =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(target.width) + static_cast<std::size_t>(x);
      const auto flags = static_cast<std::uint8_t>((s == CellState::kOccupied ? kOccupied : 0) |
                                                   (target_near[i] ? kNearOccupied : 0));
      // Coordinates relative to the target origin stay small, so float keeps sub-cell precision.
      explored_.push_back({static_cast<float>(x), static_cast<float>(y), flags});
      target_occupied_ += s == CellState::kOccupied;
      if (InSample(x, y)) {
        sampled_.push_back(explored_.back());
        sampled_occupied_ += s == CellState::kOccupied;
      }
    }
  }
}

double RegionMatcher::Psi(const Alignment& alignment) const { return PsiOver(explored_, target_occupied_, alignment); }

double RegionMatcher::CoarsePsi(const Alignment& alignment) const {
  return PsiOver(sampled_, sampled_occupied_, alignment);
}

double RegionMatcher::PsiOver(const std::vector<TargetCell>& cells, std::int64_t target_occupied,
                              const Alignment& alignment) const {
  // Window-local reference position of a target-local cell c: A c + b, with A = R(-theta) and b
  // folding in both origins (see Alignment::ToReference). The + 0.5 makes truncation round to
  // the nearest cell for the non-negative coordinates that can hit the window.
  const double c = std::cos(alignment.theta), s = std::sin(alignment.theta);
  const Eigen::Vector2d b = alignment.ToReference(target_origin_.cast<double>()) - window_->origin.cast<double>() +
                            Eigen::Vector2d(0.5, 0.5);
  const auto a00 = static_cast<float>(c), a01 = static_cast<float>(s), a10 = static_cast<float>(-s),
             a11 = static_cast<float>(c);
  const auto bx = static_cast<float>(b.x()), by = static_cast<float>(b.y());
  const int width = window_->width;
  const auto w = static_cast<float>(width), h = static_cast<float>(window_->height);
  std::int64_t aligned_occupied = 0, target_matched = 0, aligned_matched = 0;
  for (const TargetCell& t : cells) {
    const float rx = a00 * t.x + a01 * t.y + bx;
    const float ry = a10 * t.x + a11 * t.y + by;
    std::uint8_t ref = 0;
    if (rx >= 0.0f && ry >= 0.0f && rx < w && ry < h) {
      ref = window_->flags[static_cast<std::size_t>(static_cast<int>(ry)) * static_cast<std::size_t>(width) +
                          static_cast<std::size_t>(static_cast<int>(rx))];
    }
    aligned_occupied += ref & kOccupied;
    target_matched += (t.flags & kOccupied) && (ref & kNearOccupied);
    aligned_matched += (ref & kOccupied) && (t.flags & kNearOccupied);
  }
  const std::int64_t total = target_occupied + aligned_occupied;
  return total == 0 ? 0.0 : static_cast<double>(target_matched + aligned_matched) / static_cast<double>(total);
}

}  // namespace pslam
