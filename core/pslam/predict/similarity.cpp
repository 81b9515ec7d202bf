#include "pslam/predict/similarity.hpp"

#include <stdexcept>
#include <vector>

namespace pslam {

namespace {

template <typename Compared>
OverlapCounts CountOverlapWhere(const CellRaster& target, const CellRaster& aligned, int tolerance_cells,
                                Compared compared) {
  if (target.width != aligned.width || target.height != aligned.height) {
    throw std::invalid_argument("CountOverlap: rasters differ in size");
  }
  if (tolerance_cells < 0) throw std::invalid_argument("CountOverlap: negative tolerance");
  const std::vector<std::uint8_t> target_near = DilatedOccupancy(target, tolerance_cells);
  const std::vector<std::uint8_t> aligned_near = DilatedOccupancy(aligned, tolerance_cells);
  OverlapCounts counts;
  for (std::size_t i = 0; i < target.cells.size(); ++i) {
    if (!compared(i)) continue;
    if (target.cells[i] == CellState::kOccupied) {
      ++counts.target_occupied;
      counts.target_matched += aligned_near[i];
    }
    if (aligned.cells[i] == CellState::kOccupied) {
      ++counts.aligned_occupied;
      counts.aligned_matched += target_near[i];
    }
  }
  return counts;
}

}  // namespace

OverlapCounts CountOverlap(const CellRaster& target, const CellRaster& aligned, int tolerance_cells) {
  // Only the explored part of S_f is compared.
  return CountOverlapWhere(target, aligned, tolerance_cells,
                           [&](std::size_t i) { return IsExplored(target.cells[i]); });
}

OverlapCounts CountOverlap(const CellRaster& target, const CellRaster& aligned, int tolerance_cells,
                           const std::vector<std::uint8_t>& compared) {
  if (compared.size() != target.cells.size()) throw std::invalid_argument("CountOverlap: mask differs in size");
  return CountOverlapWhere(target, aligned, tolerance_cells, [&](std::size_t i) { return compared[i] != 0; });
}

double Similarity(const CellRaster& target, const CellRaster& aligned, int tolerance_cells) {
  return CountOverlap(target, aligned, tolerance_cells).Psi();
}

}  // namespace pslam
