#pragma once
// Map accuracy as the Kullback-Leibler divergence of eq. 24 of the P-SLAM paper:
//   D_KL(P || Q) = sum_i P(i) log(P(i) / Q(i)),
// P the reference map (the paper: a map built with 1000 particles), Q the evaluated map. Lower is
// better; the value is a sum, so it grows with the size of the map.
//
// What "a cell's distribution" means here, since the paper leaves it open:
// - Each cell is a Bernoulli variable (occupied / free), and the sum runs over both outcomes:
//     p log(p / q) + (1 - p) log((1 - p) / (1 - q)),  natural log (nats).
//   Summing only the occupied outcome could go negative and would ignore free space.
// - Cells are aligned by world coordinates: the reference cell's centre is looked up in the
//   evaluated map. Grids may have different extents and origins but must share the resolution.
// - Cells unknown in the reference are skipped: the reference says nothing there.
// - Cells unknown in the evaluated map count as q = 0.5 (no information), so a map that misses
//   part of the reference pays for it.
// - p and q are clamped to [1e-3, 1 - 1e-3]: certain cells would otherwise give infinite terms.
#include <cstddef>

#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

struct MapDivergence {
  double kl = 0.0;        // nats
  std::size_t cells = 0;  // reference cells compared (those known in the reference)
};

// Throws std::invalid_argument if the resolutions differ.
MapDivergence ComputeMapDivergence(const OccupancyGrid& reference, const OccupancyGrid& evaluated);

}  // namespace pslam
