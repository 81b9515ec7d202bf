#pragma once
// The similarity measure Psi of the P-SLAM paper (section III-B, eq. 3-5): a Dice coefficient over
// occupied cells only,
//   Psi = 2 |occupied in both| / (|occupied in S_f| + |occupied in aligned C_f'|),
// because most of a map is empty space and any measure that counts free cells (sum of absolute
// differences, correlation) calls every pair of rooms similar.
//
// Choices where the paper is silent:
// - Only the explored part of the target is compared: cells unexplored in the target (kUnknown)
//   are left out of all three sums. Otherwise a half-explored target would be penalised for the
//   walls the reference has in exactly the part we want to predict.
// - Psi = 0 when neither side has an occupied cell in that part: no structure, no evidence.
// - Tolerance: walls in a laser map are rasterised with a jitter of a cell, and the alignment of
//   eq. 2 comes from corners located to about a cell, so with tolerance k > 0 an occupied cell
//   counts as matched when the other side has an occupied cell within k cells (Chebyshev
//   distance). The numerator becomes (target cells matched + aligned cells matched), each side
//   counted against the other's dilation; with k = 0 both terms equal |I| and this is eq. 5
//   exactly. Identical rasters still give 1, and rasters whose occupied cells are more than k
//   cells apart still give exactly 0.
#include <cstdint>
#include <vector>

#include "pslam/predict/map_raster.hpp"

namespace pslam {

struct OverlapCounts {
  std::int64_t target_occupied = 0;   // sum of J(S_f), eq. 4
  std::int64_t aligned_occupied = 0;  // sum of J(C_f'), eq. 4
  std::int64_t target_matched = 0;    // target occupied cells with an aligned one within tolerance
  std::int64_t aligned_matched = 0;   // aligned occupied cells with a target one within tolerance

  // Eq. 5 with the tolerant numerator described above; 0 when there is no occupied cell at all.
  double Psi() const {
    const std::int64_t total = target_occupied + aligned_occupied;
    return total == 0 ? 0.0 : static_cast<double>(target_matched + aligned_matched) / static_cast<double>(total);
  }
};

// Overlap of two equally sized rasters, element by element (their origins are ignored), over the
// cells explored in 'target'. Throws std::invalid_argument if the sizes differ or
// 'tolerance_cells' is negative.
OverlapCounts CountOverlap(const CellRaster& target, const CellRaster& aligned, int tolerance_cells);
// As above, over the cells where 'compared' (row-major like the rasters) is non-zero. Both rasters
// are still dilated over everything they hold, so a cell at the edge of the compared set is matched
// by one just outside it, as an explored wall of S_f is by a reference wall in its unexplored part.
OverlapCounts CountOverlap(const CellRaster& target, const CellRaster& aligned, int tolerance_cells,
                           const std::vector<std::uint8_t>& compared);

// Psi(target, aligned): CountOverlap(...).Psi().
double Similarity(const CellRaster& target, const CellRaster& aligned, int tolerance_cells = 1);

}  // namespace pslam
