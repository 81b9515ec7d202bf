#pragma once
// Occupancy grid of log-odds cells that grows as the robot explores. Cells live in 64x64 tiles held
// by shared pointers: copying a grid copies only tile pointers, and a tile is cloned the first time
// a shared copy is written (copy on write). This is what lets hundreds of particles keep their own
// map while sharing everything they have not changed since resampling.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace pslam {

struct CellBox {  // inclusive cell-index bounds; empty when min > max
  Eigen::Vector2i min{1, 1};
  Eigen::Vector2i max{0, 0};
  bool empty() const { return min.x() > max.x() || min.y() > max.y(); }
  int width() const { return empty() ? 0 : max.x() - min.x() + 1; }
  int height() const { return empty() ? 0 : max.y() - min.y() + 1; }
  void Extend(const Eigen::Vector2i& c) {
    if (empty()) { min = max = c; return; }
    min = min.cwiseMin(c);
    max = max.cwiseMax(c);
  }
  bool Contains(const Eigen::Vector2i& c) const {
    return c.x() >= min.x() && c.y() >= min.y() && c.x() <= max.x() && c.y() <= max.y();
  }
  // Row-major index of a contained cell in a dense window over the box.
  std::size_t Index(const Eigen::Vector2i& c) const {
    return static_cast<std::size_t>(c.y() - min.y()) * static_cast<std::size_t>(width()) +
           static_cast<std::size_t>(c.x() - min.x());
  }
};

// Bounds that keep a grid finite whatever poses it is given (a wild odometry reading, a unit
// mistake): cells farther than max_extent_meters from the origin, and cells whose tile would grow
// the dense tile table past max_tile_slots, are not stored. Writes to them go nowhere and are
// counted (refused_writes), reads of them say unknown. Normal maps never come near either bound.
struct GridLimits {
  double max_extent_meters = 1e5;
  std::size_t max_tile_slots = std::size_t{1} << 20;  // 16 MiB of table: 1024 x 1024 tiles of 64 x 64 cells
};

class OccupancyGrid {
 public:
  using Cell = std::int16_t;                      // log-odds in milli-units
  static constexpr Cell kUnknown = std::numeric_limits<Cell>::min();
  static constexpr float kLogOddsPerUnit = 1e-3f;
  static constexpr int kTileBits = 6;
  static constexpr int kTileSize = 1 << kTileBits;
  static constexpr int kTileMask = kTileSize - 1;
  static constexpr float kHitOffsetScale = 254.0f;  // stored units per cell
  struct Tile {
    std::array<Cell, kTileSize * kTileSize> cells;
    // Where in each cell its hits landed on average, relative to the cell's centre, in
    // 1/kHitOffsetScale of a cell, and over how many hits (saturating): a wall that lies on a
    // cell's edge is known to lie there, not at the centre.
    std::array<std::int8_t, kTileSize * kTileSize> hit_x{}, hit_y{};
    std::array<std::uint8_t, kTileSize * kTileSize> hit_count{};
    std::uint64_t revision = 0;                    // bumped by every write batch, for change tracking
  };

  static constexpr int kMaxCellIndex = 1 << 30;  // WorldToCell saturates here (and maps NaN to -kMaxCellIndex)

  explicit OccupancyGrid(double resolution = 0.05, const GridLimits& limits = {});

  double resolution() const { return resolution_; }
  const GridLimits& limits() const { return limits_; }
  Eigen::Vector2i WorldToCell(const Eigen::Vector2d& p) const {
    return {CellIndex(p.x() / resolution_), CellIndex(p.y() / resolution_)};
  }
  Eigen::Vector2d CellCenter(const Eigen::Vector2i& c) const {
    return {(c.x() + 0.5) * resolution_, (c.y() + 0.5) * resolution_};
  }

  Cell At(int cx, int cy) const {
    const Tile* t = TileAt(cx >> kTileBits, cy >> kTileBits);
    return t ? t->cells[Local(cx, cy)] : kUnknown;
  }
  bool IsKnown(int cx, int cy) const { return At(cx, cy) != kUnknown; }
  // Log-odds of a cell; 0 (p = 0.5) for unknown cells.
  float LogOdds(int cx, int cy) const {
    const Cell c = At(cx, cy);
    return c == kUnknown ? 0.0f : static_cast<float>(c) * kLogOddsPerUnit;
  }
  float Probability(int cx, int cy) const;

  // Writable cell, creating, growing and un-sharing the tile as needed. A cell beyond the limits
  // yields a scratch cell that nothing reads, and counts as a refused write.
  Cell& MutableAt(int cx, int cy);
  // Writes to cells beyond the limits since the grid was made (copies inherit the count).
  std::uint64_t refused_writes() const { return refused_writes_; }
  // Adds `delta` (milli log-odds) to a cell, clamped to [lo, hi]; an unknown cell starts at 0.
  void AddLogOdds(int cx, int cy, int delta, int lo, int hi) {
    Cell& c = MutableAt(cx, cy);
    c = Added(c, delta, lo, hi);
  }

  // AddLogOdds for a hit that landed at `in_cell` (cells, from the cell's centre, each in
  // [-0.5, 0.5]), remembering where in the cell the hits land (HitOffset).
  void AddHit(int cx, int cy, const Eigen::Vector2f& in_cell, int delta, int lo, int hi);
  // Where the hits of a cell landed, in cells from its centre; (0, 0) for a cell never hit.
  Eigen::Vector2f HitOffset(int cx, int cy) const {
    const Tile* t = TileAt(cx >> kTileBits, cy >> kTileBits);
    if (!t) return Eigen::Vector2f::Zero();
    const int i = Local(cx, cy);
    return Eigen::Vector2f(t->hit_x[i], t->hit_y[i]) / kHitOffsetScale;
  }

  // Returns a cell to unknown; a no-op (and no tile copy) when it is unknown already.
  void Forget(int cx, int cy) {
    if (IsKnown(cx, cy)) MutableAt(cx, cy) = kUnknown;
  }

  // Bounds of all cells that have been observed at least once.
  CellBox KnownBounds() const;
  // Tile-level access for exporters and change tracking: tile coordinates are cell >> kTileBits.
  const Tile* TileAt(int tx, int ty) const {
    const int ix = tx - tile_origin_.x(), iy = ty - tile_origin_.y();
    if (ix < 0 || iy < 0 || ix >= tiles_w_ || iy >= tiles_h_) return nullptr;
    return tiles_[static_cast<std::size_t>(iy) * tiles_w_ + ix].get();
  }
  Eigen::Vector2i tile_origin() const { return tile_origin_; }
  int tiles_wide() const { return tiles_w_; }
  int tiles_high() const { return tiles_h_; }
  std::size_t AllocatedTiles() const;
  // Bytes held by tiles that no other grid shares: what this copy costs on its own.
  std::size_t UniqueBytes() const;
  // The table plus each tile's bytes divided among the grids that share it: summed over grids that
  // share tiles only with each other, every tile counts once.
  double SharedBytes() const;

  static int Local(int cx, int cy) { return ((cy & kTileMask) << kTileBits) | (cx & kTileMask); }

 private:
  static Cell Added(Cell c, int delta, int lo, int hi) {
    return static_cast<Cell>(std::clamp((c == kUnknown ? 0 : c) + delta, lo, hi));
  }
  static int CellIndex(double v) {
    const double f = std::floor(v);
    if (!(f > -kMaxCellIndex)) return -kMaxCellIndex;  // also NaN
    return f > kMaxCellIndex ? kMaxCellIndex : static_cast<int>(f);
  }
  bool EnsureTileSlot(int tx, int ty);  // false: the table may not grow to hold the tile
  // The tile of a cell, created or un-shared for writing; nullptr beyond the limits (counted).
  Tile* MutableTile(int cx, int cy);

  double resolution_;
  GridLimits limits_;
  int max_cell_ = 0;  // |cell index| bound from limits_.max_extent_meters
  std::uint64_t refused_writes_ = 0;
  Cell scratch_ = kUnknown;
  Eigen::Vector2i tile_origin_{0, 0};
  int tiles_w_ = 0;
  int tiles_h_ = 0;
  std::vector<std::shared_ptr<Tile>> tiles_;
  // Cache of the last tile written, known to be unshared; cleared on both sides when the grid is
  // copied, since the tile is shared from then on.
  mutable Tile* write_cache_ = nullptr;
  Eigen::Vector2i write_cache_tile_{0, 0};

 public:
  OccupancyGrid(const OccupancyGrid& other);
  OccupancyGrid& operator=(const OccupancyGrid& other);
  OccupancyGrid(OccupancyGrid&&) noexcept = default;
  OccupancyGrid& operator=(OccupancyGrid&&) noexcept = default;
};

// Probability of occupancy for a stored cell value (0.5 for unknown), by table lookup.
float CellProbability(OccupancyGrid::Cell c);

}  // namespace pslam
