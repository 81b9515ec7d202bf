#include "pslam/grid/prior_map.hpp"

#include <cmath>

namespace pslam {

OccupancyGrid CapPriorConfidence(const OccupancyGrid& prior, double max_probability) {
  OccupancyGrid capped = prior;
  if (!(max_probability > 0.5 && max_probability < 1.0)) return capped;
  const int cap = static_cast<int>(std::lround(std::log(max_probability / (1.0 - max_probability)) /
                                               OccupancyGrid::kLogOddsPerUnit));
  const auto beyond = [cap](OccupancyGrid::Cell c) { return c != OccupancyGrid::kUnknown && std::abs(c) > cap; };
  constexpr int n = OccupancyGrid::kTileSize;
  for (int iy = 0; iy < prior.tiles_high(); ++iy) {
    for (int ix = 0; ix < prior.tiles_wide(); ++ix) {
      const int tx = prior.tile_origin().x() + ix, ty = prior.tile_origin().y() + iy;
      const OccupancyGrid::Tile* tile = prior.TileAt(tx, ty);
      if (!tile) continue;
      for (int ly = 0; ly < n; ++ly) {
        for (int lx = 0; lx < n; ++lx) {
          const OccupancyGrid::Cell c = tile->cells[OccupancyGrid::Local(lx, ly)];
          if (!beyond(c)) continue;
          capped.MutableAt(tx * n + lx, ty * n + ly) = static_cast<OccupancyGrid::Cell>(c > 0 ? cap : -cap);
        }
      }
    }
  }
  return capped;
}

}  // namespace pslam
