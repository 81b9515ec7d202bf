#include "pslam/matching/occupancy_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "pslam/grid/cell_key.hpp"

namespace pslam {
namespace {
// Built once at load, at file scope: the matcher reads it for every cell it touches, and a
// function-local static would be checked for initialisation on every read.
struct EvidenceTable {
  std::array<float, 1 << 16> v;
  EvidenceTable() {
    for (int c = -32768; c <= 32767; ++c) {
      const float p = CellProbability(static_cast<OccupancyGrid::Cell>(c));
      v[static_cast<std::uint16_t>(c)] = std::max(0.0f, 2.0f * p - 1.0f);
    }
  }
};
const EvidenceTable kEvidence;

inline float Evidence(OccupancyGrid::Cell c) { return kEvidence.v[static_cast<std::uint16_t>(c)]; }
}  // namespace

float CellEvidence(OccupancyGrid::Cell c) { return Evidence(c); }

OccupancyField::OccupancyField(const OccupancyGrid& grid, int level, bool hit_offsets)
    : grid_(grid),
      level_(level),
      hit_offsets_(hit_offsets && level == 0),
      cell_size_(grid.resolution() * (1 << level)),
      per_cell_(static_cast<float>(1.0 / cell_size_)) {}

float OccupancyField::Coarse(int i, int j) const {
  if (level_ == 0) return Evidence(grid_.At(i, j));
  // A match reads the same few hundred pooled cells over and over: remember them. A slot taken by
  // another block only costs that block's maximum again.
  const std::uint64_t key = CellKey(i, j);
  const std::size_t index = (static_cast<std::uint32_t>(i) * 73856093u ^ static_cast<std::uint32_t>(j) * 19349663u) &
                            (kPooledSlots - 1);
  if (pooled_.empty()) pooled_.resize(kPooledSlots);
  PooledSlot& slot = pooled_[index];
  if (slot.filled && slot.key == key) return slot.value;
  const int n = 1 << level_;
  float best = 0.0f;
  if (n <= OccupancyGrid::kTileSize) {
    // Blocks are aligned to their size, tiles to theirs: one tile holds the whole block.
    const int x0 = i * n, y0 = j * n;
    if (const OccupancyGrid::Tile* tile = grid_.TileAt(x0 >> OccupancyGrid::kTileBits, y0 >> OccupancyGrid::kTileBits)) {
      for (int y = y0; y < y0 + n; ++y) {
        for (int x = x0; x < x0 + n; ++x) best = std::max(best, Evidence(tile->cells[OccupancyGrid::Local(x, y)]));
      }
    }
  } else {
    for (int y = j * n; y < (j + 1) * n; ++y) {
      for (int x = i * n; x < (i + 1) * n; ++x) best = std::max(best, Evidence(grid_.At(x, y)));
    }
  }
  slot = {key, best, true};
  return best;
}

namespace {
// A point between the centres of four cells, (i, j), (i+1, j), (i, j+1) and (i+1, j+1): the
// first one's indices and the point's fractions of the way to the others.
struct Stencil {
  int i, j;
  float fu, fv;
  Stencil(float x, float y, double cell_size) {
    // Sample positions are cell centres: shift by half a cell before splitting into index + fraction.
    const double u = x / cell_size - 0.5, v = y / cell_size - 0.5;
    const double fu0 = std::floor(u), fv0 = std::floor(v);
    i = static_cast<int>(fu0);
    j = static_cast<int>(fv0);
    fu = static_cast<float>(u - fu0);
    fv = static_cast<float>(v - fv0);
  }
  float Interpolate(const float (&c)[4], Eigen::Vector2f* gradient, float per_cell) const {
    if (gradient) {
      gradient->x() = ((1 - fv) * (c[1] - c[0]) + fv * (c[3] - c[2])) * per_cell;
      gradient->y() = ((1 - fu) * (c[2] - c[0]) + fu * (c[3] - c[1])) * per_cell;
    }
    return (1 - fv) * ((1 - fu) * c[0] + fu * c[1]) + fv * ((1 - fu) * c[2] + fu * c[3]);
  }
};
}  // namespace

void OccupancyField::Corners(int i, int j, float (&value)[4], HitOffsets* offset) const {
  if (level_ > 0) {
    // Neighbouring beams mostly fall between the same four coarse cells.
    if (!last_corners_.filled || last_corners_.i != i || last_corners_.j != j) {
      last_corners_ = {i, j, {Coarse(i, j), Coarse(i + 1, j), Coarse(i, j + 1), Coarse(i + 1, j + 1)}, true};
    }
    std::copy(std::begin(last_corners_.value), std::end(last_corners_.value), value);
    return;
  }
  constexpr int kBits = OccupancyGrid::kTileBits;
  const int tx = i >> kBits, ty = j >> kBits;
  const int cx[4] = {i, i + 1, i, i + 1}, cy[4] = {j, j, j + 1, j + 1};
  const bool one_tile = ((i + 1) >> kBits) == tx && ((j + 1) >> kBits) == ty;  // all but one row and column in 64
  const OccupancyGrid::Tile* shared = one_tile ? grid_.TileAt(tx, ty) : nullptr;
  for (int k = 0; k < 4; ++k) {
    const OccupancyGrid::Tile* tile = one_tile ? shared : grid_.TileAt(cx[k] >> kBits, cy[k] >> kBits);
    const int local = OccupancyGrid::Local(cx[k], cy[k]);
    value[k] = tile ? Evidence(tile->cells[local]) : 0.0f;
    if (offset) {
      offset->x[k] = tile ? tile->hit_x[local] : 0.0f;
      offset->y[k] = tile ? tile->hit_y[local] : 0.0f;
    }
  }
}

float OccupancyField::Value(const Eigen::Vector2f& world, Eigen::Vector2f* gradient) const {
  const Stencil at(world.x(), world.y(), cell_size_);
  float value[4];
  HitOffsets offset;
  Corners(at.i, at.j, value, hit_offsets_ ? &offset : nullptr);
  if (!hit_offsets_) return at.Interpolate(value, gradient, per_cell_);
  // A wall whose surface lies on a cell's edge is drawn by its hits near that edge: read the field
  // shifted by where the hits around the point landed (weighted by each cell's share of the
  // evidence there), so that the evidence peaks on the surface instead of half a cell behind it.
  const float w[4] = {(1 - at.fu) * (1 - at.fv) * value[0], at.fu * (1 - at.fv) * value[1],
                      (1 - at.fu) * at.fv * value[2], at.fu * at.fv * value[3]};
  const float total = w[0] + w[1] + w[2] + w[3];
  if (total <= 0.0f) return at.Interpolate(value, gradient, per_cell_);
  const float to_cells = 1.0f / (total * OccupancyGrid::kHitOffsetScale);
  const float shift_u = (w[0] * offset.x[0] + w[1] * offset.x[1] + w[2] * offset.x[2] + w[3] * offset.x[3]) * to_cells;
  const float shift_v = (w[0] * offset.y[0] + w[1] * offset.y[1] + w[2] * offset.y[2] + w[3] * offset.y[3]) * to_cells;
  Stencil shifted = at;
  shifted.fu -= shift_u;
  shifted.fv -= shift_v;
  if (shifted.fu < 0.0f || shifted.fu >= 1.0f || shifted.fv < 0.0f || shifted.fv >= 1.0f) {
    // Shifted past the four cells' centres: the next four.
    const float cell = static_cast<float>(cell_size_);
    shifted = Stencil(world.x() - shift_u * cell, world.y() - shift_v * cell, cell_size_);
    Corners(shifted.i, shifted.j, value, nullptr);
  }
  return shifted.Interpolate(value, gradient, per_cell_);
}

}  // namespace pslam
