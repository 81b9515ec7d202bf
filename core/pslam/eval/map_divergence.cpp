#include "pslam/eval/map_divergence.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pslam {
namespace {

constexpr double kMinProbability = 1e-3;

double Clamped(double p) { return std::clamp(p, kMinProbability, 1.0 - kMinProbability); }

// KL divergence between two Bernoulli distributions, both outcomes.
double BernoulliKl(double p, double q) { return p * std::log(p / q) + (1.0 - p) * std::log((1.0 - p) / (1.0 - q)); }

}  // namespace

MapDivergence ComputeMapDivergence(const OccupancyGrid& reference, const OccupancyGrid& evaluated) {
  const double res = reference.resolution();
  if (std::abs(res - evaluated.resolution()) > 1e-9 * res) {
    std::ostringstream msg;
    msg << "map resolutions differ: reference " << res << " m, evaluated " << evaluated.resolution() << " m";
    throw std::invalid_argument(msg.str());
  }
  MapDivergence result;
  // Walk the reference tile by tile: only allocated tiles can hold known cells.
  const Eigen::Vector2i tile0 = reference.tile_origin();
  for (int ty = tile0.y(); ty < tile0.y() + reference.tiles_high(); ++ty) {
    for (int tx = tile0.x(); tx < tile0.x() + reference.tiles_wide(); ++tx) {
      const OccupancyGrid::Tile* tile = reference.TileAt(tx, ty);
      if (!tile) continue;
      for (int ly = 0; ly < OccupancyGrid::kTileSize; ++ly) {
        for (int lx = 0; lx < OccupancyGrid::kTileSize; ++lx) {
          const Eigen::Vector2i cell(tx * OccupancyGrid::kTileSize + lx, ty * OccupancyGrid::kTileSize + ly);
          const OccupancyGrid::Cell ref_cell = tile->cells[OccupancyGrid::Local(cell.x(), cell.y())];
          if (ref_cell == OccupancyGrid::kUnknown) continue;
          const Eigen::Vector2i other = evaluated.WorldToCell(reference.CellCenter(cell));
          // CellProbability gives 0.5 for unknown cells, which is exactly the documented q.
          const double q = CellProbability(evaluated.At(other.x(), other.y()));
          result.kl += BernoulliKl(Clamped(CellProbability(ref_cell)), Clamped(q));
          ++result.cells;
        }
      }
    }
  }
  return result;
}

}  // namespace pslam
