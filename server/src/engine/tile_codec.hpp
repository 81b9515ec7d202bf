#pragma once
// Map tiles on the wire and on disk. Both forms are zlib streams of one OccupancyGrid tile
// (64 x 64 cells, row-major, row 0 at the lowest y):
//   - stored: int16 little-endian log-odds in milli-units, OccupancyGrid::kUnknown for unknown
//     (lossless, so a stored map reloads exactly);
//   - live: one byte per cell, occupancy in percent 0..100, 255 for unknown (what a viewer draws).
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "model/checkpoint.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam::server {

inline constexpr std::uint8_t kLiveUnknown = 255;

// A null 'tile' encodes as all unknown (a tile the best particle's map does not have).
std::vector<std::uint8_t> EncodeStoredTile(const OccupancyGrid::Tile* tile);
std::vector<std::uint8_t> EncodeLiveTile(const OccupancyGrid::Tile* tile);
// The live form of a stored tile; nullopt if 'stored' is corrupt.
std::optional<std::vector<std::uint8_t>> StoredToLiveTile(std::span<const std::uint8_t> stored);

// The grid made of stored tiles; corrupt tiles are skipped.
OccupancyGrid GridFromTiles(const std::vector<TileRow>& tiles, double resolution);

}  // namespace pslam::server
