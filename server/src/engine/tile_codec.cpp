#include "engine/tile_codec.hpp"

#include <bit>
#include <cmath>
#include <cstring>

#include "common/zlib_codec.hpp"

namespace pslam::server {
namespace {

static_assert(std::endian::native == std::endian::little, "tiles are int16 little-endian; add byte swapping here");
constexpr std::size_t kCells = OccupancyGrid::kTileSize * OccupancyGrid::kTileSize;

std::uint8_t LivePixel(OccupancyGrid::Cell cell) {
  if (cell == OccupancyGrid::kUnknown) return kLiveUnknown;
  return static_cast<std::uint8_t>(std::lround(CellProbability(cell) * 100.0f));
}

std::optional<std::vector<OccupancyGrid::Cell>> DecodeStored(std::span<const std::uint8_t> stored) {
  const auto raw = ZlibDecompress(stored, kCells * sizeof(OccupancyGrid::Cell));
  if (!raw || raw->size() != kCells * sizeof(OccupancyGrid::Cell)) return std::nullopt;
  std::vector<OccupancyGrid::Cell> cells(kCells);
  std::memcpy(cells.data(), raw->data(), raw->size());
  return cells;
}

}  // namespace

std::vector<std::uint8_t> EncodeStoredTile(const OccupancyGrid::Tile* tile) {
  std::vector<std::uint8_t> raw(kCells * sizeof(OccupancyGrid::Cell));
  if (tile) {
    std::memcpy(raw.data(), tile->cells.data(), raw.size());
  } else {
    const OccupancyGrid::Cell unknown = OccupancyGrid::kUnknown;
    for (std::size_t i = 0; i < kCells; ++i) std::memcpy(&raw[i * sizeof unknown], &unknown, sizeof unknown);
  }
  return ZlibCompress(raw);
}

std::vector<std::uint8_t> EncodeLiveTile(const OccupancyGrid::Tile* tile) {
  std::vector<std::uint8_t> raw(kCells, kLiveUnknown);
  if (tile) {
    for (std::size_t i = 0; i < kCells; ++i) raw[i] = LivePixel(tile->cells[i]);
  }
  return ZlibCompress(raw);
}

std::optional<std::vector<std::uint8_t>> StoredToLiveTile(std::span<const std::uint8_t> stored) {
  const auto cells = DecodeStored(stored);
  if (!cells) return std::nullopt;
  std::vector<std::uint8_t> raw(kCells);
  for (std::size_t i = 0; i < kCells; ++i) raw[i] = LivePixel((*cells)[i]);
  return ZlibCompress(raw);
}

OccupancyGrid GridFromTiles(const std::vector<TileRow>& tiles, double resolution) {
  OccupancyGrid grid(resolution);
  for (const TileRow& t : tiles) {
    if (t.size != OccupancyGrid::kTileSize) continue;
    const auto cells = DecodeStored(t.data);
    if (!cells) continue;
    for (int ly = 0; ly < OccupancyGrid::kTileSize; ++ly) {
      for (int lx = 0; lx < OccupancyGrid::kTileSize; ++lx) {
        const OccupancyGrid::Cell c = (*cells)[static_cast<std::size_t>(ly * OccupancyGrid::kTileSize + lx)];
        if (c != OccupancyGrid::kUnknown) {
          grid.MutableAt(t.tx * OccupancyGrid::kTileSize + lx, t.ty * OccupancyGrid::kTileSize + ly) = c;
        }
      }
    }
  }
  return grid;
}

}  // namespace pslam::server
