#include "pslam/predict/similarity.hpp"

#include <stdexcept>
#include <vector>

namespace pslam {

OverlapCounts CountOverlap(const CellRaster& target, const CellRaster& aligned, int tolerance_cells) {
  if (target.width != aligned.width || target.height != aligned.height) {
    throw std::invalid_argument("CountOverlap: rasters differ in size");
  }
  if (tolerance_cells < 0) throw std::invalid_argument("CountOverlap: negative tolerance");
  const std::vector<std::uint8_t> target_near = DilatedOccupancy(target, tolerance_cells);
  const std::vector<std::uint8_t> aligned_near = DilatedOccupancy(aligned, tolerance_cells);
  OverlapCounts counts;
  for (std::size_t i = 0; i < target.cells.size(); ++i) {
    if (!IsExplored(target.cells[i])) continue;  // only the explored part of S_f is compared
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

double Similarity(const CellRaster& target, const CellRaster& aligned, int tolerance_cells) {
  return CountOverlap(target, aligned, tolerance_cells).Psi();
}

}  // namespace pslam
