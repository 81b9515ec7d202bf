#include "service/map_export.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

#include "common/png_writer.hpp"
#include "engine/tile_codec.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam::server {

std::string MapPng(const OccupancyGrid& grid) {
  const std::vector<std::uint8_t> png = EncodeMapPng(grid);
  return std::string(png.begin(), png.end());
}

std::string MapPgm(const OccupancyGrid& grid) { return MapPgmBytes(RenderMapImage(grid)); }

std::string MapYaml(const OccupancyGrid& grid, const std::string& image_name) {
  return MapYamlText(RenderMapImage(grid), image_name);
}

nlohmann::json MapMetadata(const OccupancyGrid& grid, bool live) {
  const MapImage image = RenderMapImage(grid);
  const CellBox known = grid.KnownBounds();
  nlohmann::json tiles = nlohmann::json::array();
  const Eigen::Vector2i origin = grid.tile_origin();
  for (int iy = 0; iy < grid.tiles_high(); ++iy) {
    for (int ix = 0; ix < grid.tiles_wide(); ++ix) {
      if (const OccupancyGrid::Tile* t = grid.TileAt(origin.x() + ix, origin.y() + iy)) {
        tiles.push_back({{"x", origin.x() + ix}, {"y", origin.y() + iy}, {"revision", t->revision}});
      }
    }
  }
  nlohmann::json j = {{"live", live},
                      {"resolution", grid.resolution()},
                      {"tile_size", OccupancyGrid::kTileSize},
                      {"image", {{"width", image.width}, {"height", image.height},
                                 {"origin", {image.origin.x(), image.origin.y()}}}},
                      {"tiles", tiles}};
  if (!known.empty()) {
    j["known_cells"] = {{"min", {known.min.x(), known.min.y()}}, {"max", {known.max.x(), known.max.y()}}};
  } else {
    j["known_cells"] = nullptr;
  }
  return j;
}

std::optional<Bytes> MapTile(const OccupancyGrid& grid, int tx, int ty) {
  const OccupancyGrid::Tile* tile = grid.TileAt(tx, ty);
  if (!tile) return std::nullopt;
  return EncodeTileFrame(tx, ty, tile->revision, EncodeLiveTile(tile));
}

Overlay HypothesisOverlay(const HypothesisRecord& h, double resolution) {
  Overlay o;
  if (h.cells.empty()) {
    // Nothing predicted: a single transparent pixel at the target, so clients need no special case.
    o.width = o.height = 1;
    o.origin_x = h.target_cell.x * resolution;
    o.origin_y = h.target_cell.y * resolution;
    const std::vector<std::uint8_t> pixel(4, 0);
    const auto png = EncodePng(1, 1, 4, pixel);
    o.png.assign(png.begin(), png.end());
    return o;
  }
  int min_x = INT_MAX, min_y = INT_MAX, max_x = INT_MIN, max_y = INT_MIN;
  for (const PredictedCell& c : h.cells) {
    min_x = std::min(min_x, c.x);
    min_y = std::min(min_y, c.y);
    max_x = std::max(max_x, c.x);
    max_y = std::max(max_y, c.y);
  }
  o.width = max_x - min_x + 1;
  o.height = max_y - min_y + 1;
  o.origin_x = min_x * resolution;
  o.origin_y = min_y * resolution;
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(o.width) * static_cast<std::size_t>(o.height) * 4, 0);
  for (const PredictedCell& c : h.cells) {
    const std::size_t row = static_cast<std::size_t>(max_y - c.y);  // row 0 is the top (highest y)
    const std::size_t at = (row * static_cast<std::size_t>(o.width) + static_cast<std::size_t>(c.x - min_x)) * 4;
    const float p = std::clamp(c.occupancy, 0.0f, 1.0f);
    const bool occupied = p >= 0.5f;
    rgba[at] = occupied ? 230 : 40;
    rgba[at + 1] = occupied ? 40 : 200;
    rgba[at + 2] = 40;
    rgba[at + 3] = static_cast<std::uint8_t>(std::lround(80.0f + 175.0f * std::abs(p - 0.5f) * 2.0f));
  }
  const auto png = EncodePng(o.width, o.height, 4, rgba);
  o.png.assign(png.begin(), png.end());
  return o;
}

}  // namespace pslam::server
