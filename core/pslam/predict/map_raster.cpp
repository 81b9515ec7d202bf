#include "pslam/predict/map_raster.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {
namespace {

double MilliLogOdds(double p) { return 1000.0 * std::log(p / (1.0 - p)); }

}  // namespace

CellClassifier::CellClassifier(const CellStateThresholds& thresholds)
    : occupied_above_(MilliLogOdds(thresholds.occupied_above)), free_below_(MilliLogOdds(thresholds.free_below)) {}

CellRaster RasterizeRegion(const OccupancyGrid& grid, const CellBox& box, const CellClassifier& classify) {
  if (box.empty()) return {};
  CellRaster raster(box.min, box.width(), box.height());
  constexpr int kTile = OccupancyGrid::kTileSize;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    CellState* row = &raster.Local(0, y - box.min.y());
    int x = box.min.x();
    while (x <= box.max.x()) {
      // One tile lookup per run of cells that share a tile; a missing tile stays kUnknown.
      const int run_end = std::min(box.max.x(), ((x >> OccupancyGrid::kTileBits) + 1) * kTile - 1);
      const OccupancyGrid::Tile* tile = grid.TileAt(x >> OccupancyGrid::kTileBits, y >> OccupancyGrid::kTileBits);
      if (tile) {
        for (int cx = x; cx <= run_end; ++cx) {
          row[cx - box.min.x()] = classify(tile->cells[OccupancyGrid::Local(cx, y)]);
        }
      }
      x = run_end + 1;
    }
  }
  return raster;
}

// A separable max filter: a row pass, then a column pass, each touching only marked cells.
std::vector<std::uint8_t> DilatedOccupancy(const CellRaster& raster, int radius) {
  const int w = raster.width, h = raster.height;
  std::vector<std::uint8_t> occupied(raster.cells.size());
  for (std::size_t i = 0; i < occupied.size(); ++i) occupied[i] = raster.cells[i] == CellState::kOccupied;
  if (radius == 0) return occupied;
  std::vector<std::uint8_t> rows(occupied.size(), 0), out(occupied.size(), 0);
  auto at = [w](int x, int y) {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!occupied[at(x, y)]) continue;
      for (int xx = std::max(0, x - radius); xx <= std::min(w - 1, x + radius); ++xx) rows[at(xx, y)] = 1;
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!rows[at(x, y)]) continue;
      for (int yy = std::max(0, y - radius); yy <= std::min(h - 1, y + radius); ++yy) out[at(x, yy)] = 1;
    }
  }
  return out;
}

}  // namespace pslam
