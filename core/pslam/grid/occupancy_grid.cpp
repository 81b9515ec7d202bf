#include "pslam/grid/occupancy_grid.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace pslam {
namespace {

struct ProbabilityTable {
  std::vector<float> p = std::vector<float>(1 << 16);
  ProbabilityTable() {
    for (int v = std::numeric_limits<std::int16_t>::min(); v <= std::numeric_limits<std::int16_t>::max(); ++v) {
      const double l = v * static_cast<double>(OccupancyGrid::kLogOddsPerUnit);
      p[static_cast<std::uint16_t>(v)] = v == OccupancyGrid::kUnknown ? 0.5f : static_cast<float>(1.0 - 1.0 / (1.0 + std::exp(l)));
    }
  }
};
const ProbabilityTable& Table() {
  static const ProbabilityTable table;
  return table;
}

}  // namespace

float CellProbability(OccupancyGrid::Cell c) { return Table().p[static_cast<std::uint16_t>(c)]; }

OccupancyGrid::OccupancyGrid(double resolution, const GridLimits& limits)
    : resolution_(resolution),
      limits_(limits),
      max_cell_(static_cast<int>(std::clamp(limits.max_extent_meters / resolution, 0.0, kMaxCellIndex - 1.0))) {}

OccupancyGrid::OccupancyGrid(const OccupancyGrid& other)
    : resolution_(other.resolution_),
      limits_(other.limits_),
      max_cell_(other.max_cell_),
      refused_writes_(other.refused_writes_),
      tile_origin_(other.tile_origin_),
      tiles_w_(other.tiles_w_),
      tiles_h_(other.tiles_h_),
      tiles_(other.tiles_) {
  other.write_cache_ = nullptr;
}

OccupancyGrid& OccupancyGrid::operator=(const OccupancyGrid& other) {
  if (this != &other) {
    resolution_ = other.resolution_;
    limits_ = other.limits_;
    max_cell_ = other.max_cell_;
    refused_writes_ = other.refused_writes_;
    tile_origin_ = other.tile_origin_;
    tiles_w_ = other.tiles_w_;
    tiles_h_ = other.tiles_h_;
    tiles_ = other.tiles_;
    write_cache_ = nullptr;
    other.write_cache_ = nullptr;
  }
  return *this;
}

float OccupancyGrid::Probability(int cx, int cy) const { return CellProbability(At(cx, cy)); }

bool OccupancyGrid::EnsureTileSlot(int tx, int ty) {
  if (tiles_w_ > 0 && tx >= tile_origin_.x() && ty >= tile_origin_.y() && tx < tile_origin_.x() + tiles_w_ &&
      ty < tile_origin_.y() + tiles_h_) {
    return true;
  }
  // Grow with a margin so that a robot driving along an edge does not regrow on every tile.
  constexpr int kMargin = 4;
  Eigen::Vector2i lo(tx, ty), hi(tx, ty);
  if (tiles_w_ > 0) {
    lo = lo.cwiseMin(tile_origin_);
    hi = hi.cwiseMax(tile_origin_ + Eigen::Vector2i(tiles_w_ - 1, tiles_h_ - 1));
  }
  const auto slots = [](const Eigen::Vector2i& a, const Eigen::Vector2i& b) {
    return static_cast<std::int64_t>(b.x() - a.x() + 1) * (b.y() - a.y() + 1);
  };
  // The table is dense between the farthest tiles: refuse what would make it too large.
  const auto max_slots = static_cast<std::int64_t>(limits_.max_tile_slots);
  if (slots(lo, hi) > max_slots) return false;
  const Eigen::Vector2i exact_lo = lo, exact_hi = hi;
  if (tx < tile_origin_.x() || tiles_w_ == 0) lo.x() -= kMargin;
  if (ty < tile_origin_.y() || tiles_w_ == 0) lo.y() -= kMargin;
  if (tx >= tile_origin_.x() + tiles_w_ || tiles_w_ == 0) hi.x() += kMargin;
  if (ty >= tile_origin_.y() + tiles_h_ || tiles_w_ == 0) hi.y() += kMargin;
  if (slots(lo, hi) > max_slots) {
    lo = exact_lo;
    hi = exact_hi;
  }
  const int w = hi.x() - lo.x() + 1, h = hi.y() - lo.y() + 1;
  std::vector<std::shared_ptr<Tile>> grown(static_cast<std::size_t>(w) * h);
  for (int iy = 0; iy < tiles_h_; ++iy) {
    for (int ix = 0; ix < tiles_w_; ++ix) {
      const int nx = ix + tile_origin_.x() - lo.x(), ny = iy + tile_origin_.y() - lo.y();
      grown[static_cast<std::size_t>(ny) * w + nx] = std::move(tiles_[static_cast<std::size_t>(iy) * tiles_w_ + ix]);
    }
  }
  tiles_ = std::move(grown);
  tile_origin_ = lo;
  tiles_w_ = w;
  tiles_h_ = h;
  return true;
}

OccupancyGrid::Tile* OccupancyGrid::MutableTile(int cx, int cy) {
  const int tx = cx >> kTileBits, ty = cy >> kTileBits;
  if (write_cache_ && write_cache_tile_.x() == tx && write_cache_tile_.y() == ty) return write_cache_;
  if (std::abs(cx) > max_cell_ || std::abs(cy) > max_cell_ || !EnsureTileSlot(tx, ty)) {
    ++refused_writes_;
    return nullptr;
  }
  auto& slot = tiles_[static_cast<std::size_t>(ty - tile_origin_.y()) * tiles_w_ + (tx - tile_origin_.x())];
  if (!slot) {
    slot = std::make_shared<Tile>();
    slot->cells.fill(kUnknown);
  } else if (slot.use_count() > 1) {
    slot = std::make_shared<Tile>(*slot);
  } else {
    // Another grid may just have released its copy of this tile; see its writes before ours.
    std::atomic_thread_fence(std::memory_order_acquire);
  }
  ++slot->revision;
  write_cache_ = slot.get();
  write_cache_tile_ = {tx, ty};
  return write_cache_;
}

OccupancyGrid::Cell& OccupancyGrid::MutableAt(int cx, int cy) {
  Tile* tile = MutableTile(cx, cy);
  if (!tile) {
    scratch_ = kUnknown;
    return scratch_;
  }
  return tile->cells[Local(cx, cy)];
}

void OccupancyGrid::AddHit(int cx, int cy, const Eigen::Vector2f& in_cell, int delta, int lo, int hi) {
  Tile* tile = MutableTile(cx, cy);
  if (!tile) return;
  const int i = Local(cx, cy);
  Cell& c = tile->cells[i];
  // The mean of every hit since the cell last turned occupied: the first hits anchor the surface,
  // as they anchor the map, and the later ones, seen from poses that carry their own errors,
  // refine it without dragging it along.
  std::uint8_t& count = tile->hit_count[i];
  if (c == kUnknown || c <= 0) count = 0;
  c = Added(c, delta, lo, hi);
  if (count < 255) ++count;
  const auto average = [count](std::int8_t& mean, float position) {
    const float target = std::clamp(position, -0.5f, 0.5f) * kHitOffsetScale;
    const float updated = mean + (target - mean) / static_cast<float>(count);
    mean = static_cast<std::int8_t>(std::lround(std::clamp(updated, -127.0f, 127.0f)));
  };
  average(tile->hit_x[i], in_cell.x());
  average(tile->hit_y[i], in_cell.y());
}

CellBox OccupancyGrid::KnownBounds() const {
  CellBox box;
  for (int iy = 0; iy < tiles_h_; ++iy) {
    for (int ix = 0; ix < tiles_w_; ++ix) {
      const Tile* t = tiles_[static_cast<std::size_t>(iy) * tiles_w_ + ix].get();
      if (!t) continue;
      const int bx = (ix + tile_origin_.x()) * kTileSize, by = (iy + tile_origin_.y()) * kTileSize;
      for (int ly = 0; ly < kTileSize; ++ly) {
        for (int lx = 0; lx < kTileSize; ++lx) {
          if (t->cells[(ly << kTileBits) | lx] != kUnknown) box.Extend({bx + lx, by + ly});
        }
      }
    }
  }
  return box;
}

std::size_t OccupancyGrid::AllocatedTiles() const {
  return static_cast<std::size_t>(std::count_if(tiles_.begin(), tiles_.end(), [](const auto& t) { return t != nullptr; }));
}

std::size_t OccupancyGrid::UniqueBytes() const {
  std::size_t bytes = tiles_.size() * sizeof(std::shared_ptr<Tile>);
  for (const auto& t : tiles_) {
    if (t && t.use_count() == 1) bytes += sizeof(Tile);
  }
  return bytes;
}

double OccupancyGrid::SharedBytes() const {
  double bytes = static_cast<double>(tiles_.size() * sizeof(std::shared_ptr<Tile>));
  for (const auto& t : tiles_) {
    if (t) bytes += static_cast<double>(sizeof(Tile)) / static_cast<double>(t.use_count());
  }
  return bytes;
}

}  // namespace pslam
