#include "pslam/sim/wall_moves.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "pslam/sim/flood_fill.hpp"

namespace pslam {
namespace {

constexpr int kMaxThickness = 6;  // cells: 0.3 m at 0.05 m
constexpr int kMargin = 3;        // cells kept free around a moved piece, along it

// A candidate piece in the frame where the wall runs along u: cells (u0..u0+len-1, v0..v0+t-1).
struct Piece {
  bool along_x = true;
  int u0 = 0, v0 = 0, len = 0, t = 0;
};

Eigen::Vector2i Cell(bool along_x, int u, int v) { return along_x ? Eigen::Vector2i(u, v) : Eigen::Vector2i(v, u); }

bool AllAre(const World& w, bool along_x, int u0, int u1, int v0, int v1, WorldCell value) {
  for (int u = u0; u <= u1; ++u) {
    for (int v = v0; v <= v1; ++v) {
      if (w.At(Cell(along_x, u, v)) != value) return false;
    }
  }
  return true;
}

// Every piece of wall running along u (x when along_x), stepping by half its length.
std::vector<Piece> FindPieces(const World& w, bool along_x, int len) {
  const CellBox& b = w.bounds();
  const int u_min = along_x ? b.min.x() : b.min.y(), u_max = along_x ? b.max.x() : b.max.y();
  const int v_min = along_x ? b.min.y() : b.min.x(), v_max = along_x ? b.max.y() : b.max.x();
  std::vector<Piece> pieces;
  for (int v0 = v_min + 1; v0 < v_max; ++v0) {
    for (int u0 = u_min; u0 + len - 1 <= u_max; u0 += len / 2) {
      // The wall's first row: free below it, occupied here, all along.
      if (!AllAre(w, along_x, u0, u0 + len - 1, v0 - 1, v0 - 1, WorldCell::kFree)) continue;
      int t = 0;
      while (t < kMaxThickness && AllAre(w, along_x, u0, u0 + len - 1, v0 + t, v0 + t, WorldCell::kOccupied)) ++t;
      if (t == 0 || t == kMaxThickness) continue;
      if (!AllAre(w, along_x, u0, u0 + len - 1, v0 + t, v0 + t, WorldCell::kFree)) continue;
      pieces.push_back({along_x, u0, v0, len, t});
    }
  }
  return pieces;
}

// A free-standing obstacle: its cells, each 4-connected to the others.
struct Block {
  std::vector<Eigen::Vector2i> cells;
  CellBox box;
};

std::vector<Block> FindBlocks(const World& w) {
  const CellBox& b = w.bounds();
  std::vector<bool> seen(static_cast<std::size_t>(b.width()) * static_cast<std::size_t>(b.height()), false);
  std::vector<Block> blocks;
  const auto occupied = [&](const Eigen::Vector2i& c) { return w.IsOccupied(c); };
  for (int y = b.min.y(); y <= b.max.y(); ++y) {
    for (int x = b.min.x(); x <= b.max.x(); ++x) {
      const Eigen::Vector2i start(x, y);
      if (!w.IsOccupied(start) || seen[BoundsIndex(w, start)]) continue;
      const std::vector<bool> mask = FloodFill4(w, start, occupied);
      Block block;
      bool touches_unknown = false;
      for (int yy = b.min.y(); yy <= b.max.y(); ++yy) {
        for (int xx = b.min.x(); xx <= b.max.x(); ++xx) {
          const Eigen::Vector2i c(xx, yy);
          if (!mask[BoundsIndex(w, c)]) continue;
          seen[BoundsIndex(w, c)] = true;
          block.cells.push_back(c);
          block.box.Extend(c);
          for (const Eigen::Vector2i& d : {Eigen::Vector2i(1, 0), Eigen::Vector2i(-1, 0), Eigen::Vector2i(0, 1), Eigen::Vector2i(0, -1)}) {
            touches_unknown |= w.At(c + d) == WorldCell::kUnknown;
          }
        }
      }
      if (!touches_unknown) blocks.push_back(std::move(block));
    }
  }
  return blocks;
}

// Moves the block by 'd' if its new place and 'clearance' cells around it are free (or its own).
bool MoveBlock(World& w, const Block& block, const Eigen::Vector2i& d, int clearance) {
  for (const Eigen::Vector2i& c : block.cells) {
    if (!w.IsOccupied(c)) return false;  // an earlier move changed it
  }
  const auto own = [&](const Eigen::Vector2i& c) { return block.box.Contains(c) && w.IsOccupied(c); };
  for (int y = block.box.min.y() + d.y() - clearance; y <= block.box.max.y() + d.y() + clearance; ++y) {
    for (int x = block.box.min.x() + d.x() - clearance; x <= block.box.max.x() + d.x() + clearance; ++x) {
      const Eigen::Vector2i c(x, y);
      if (!w.IsFree(c) && !own(c)) return false;
    }
  }
  for (const Eigen::Vector2i& c : block.cells) w.Set(c, WorldCell::kFree);
  for (const Eigen::Vector2i& c : block.cells) w.Set(c + d, WorldCell::kOccupied);
  return true;
}

// Whether 'seen' shows at least half of the faces of these cells as walls (within one cell).
bool Seen(const World& w, const OccupancyGrid* seen, const std::vector<Eigen::Vector2i>& cells) {
  if (!seen) return true;
  int faces = 0, shown = 0;
  for (const Eigen::Vector2i& c : cells) {
    bool face = false;
    for (const Eigen::Vector2i& d : {Eigen::Vector2i(1, 0), Eigen::Vector2i(-1, 0), Eigen::Vector2i(0, 1), Eigen::Vector2i(0, -1)}) {
      face |= w.IsFree(c + d);
    }
    if (!face) continue;
    ++faces;
    bool wall = false;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) wall |= seen->Probability(c.x() + dx, c.y() + dy) > 0.5f;
    }
    shown += wall;
  }
  return faces > 0 && 2 * shown >= faces;
}

CellBox Box(const Piece& p, int dv) {
  CellBox box;
  box.Extend(Cell(p.along_x, p.u0, p.v0 + dv));
  box.Extend(Cell(p.along_x, p.u0 + p.len - 1, p.v0 + dv + p.t - 1));
  return box;
}

}  // namespace

World MoveWalls(const World& world, const Eigen::Vector2d& keep_free, const WallMoveOptions& o,
                std::vector<WallMove>* moves, const OccupancyGrid* seen) {
  const double res = world.resolution();
  const int len = std::max(4, static_cast<int>(std::lround(o.length / res)));
  const int shift = std::max(1, static_cast<int>(std::lround(o.shift / res)));
  const int clearance = static_cast<int>(std::lround(o.clearance / res));
  std::vector<Piece> pieces = FindPieces(world, true, len);
  const std::vector<Piece> vertical = FindPieces(world, false, len);
  pieces.insert(pieces.end(), vertical.begin(), vertical.end());
  const std::vector<Block> blocks = FindBlocks(world);
  // Candidates: pieces by index, then blocks (index - pieces.size()), in an order fixed by the seed.
  std::vector<std::size_t> order(pieces.size() + blocks.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937_64 rng(o.seed);
  std::shuffle(order.begin(), order.end(), rng);

  World out = world;
  int moved = 0;
  for (const std::size_t index : order) {
    if (moved >= o.count) break;
    if (index >= pieces.size()) {
      const Block& block = blocks[index - pieces.size()];
      const Eigen::Vector2d centre = (block.box.min + block.box.max).cast<double>() * 0.5 * res;
      if ((centre - keep_free).norm() < o.keep_away + o.shift + 0.5 * block.box.width() * res) continue;
      if (!Seen(world, seen, block.cells)) continue;
      for (const Eigen::Vector2i& d : {Eigen::Vector2i(shift, 0), Eigen::Vector2i(-shift, 0), Eigen::Vector2i(0, shift),
                                       Eigen::Vector2i(0, -shift)}) {
        if (!MoveBlock(out, block, d, clearance)) continue;
        CellBox to = block.box;
        to.min += d;
        to.max += d;
        if (moves) moves->push_back({block.box, to});
        ++moved;
        break;
      }
      continue;
    }
    const Piece& p = pieces[index];
    const CellBox from = Box(p, 0);
    const Eigen::Vector2d centre = (from.min + from.max).cast<double>() * 0.5 * res;
    if ((centre - keep_free).norm() < o.keep_away + o.shift) continue;
    std::vector<Eigen::Vector2i> cells;
    for (int u = p.u0; u < p.u0 + len; ++u) {
      for (int v = 0; v < p.t; ++v) cells.push_back(Cell(p.along_x, u, p.v0 + v));
    }
    if (!Seen(world, seen, cells)) continue;
    // Still the piece it was (an earlier move did not take or touch it)?
    if (!AllAre(out, p.along_x, p.u0, p.u0 + len - 1, p.v0, p.v0 + p.t - 1, WorldCell::kOccupied)) continue;
    for (const int side : {1, -1}) {
      const int dv = side * shift;
      // The new place, its clearance beyond and the way there must be free, with a margin along.
      const int near = side > 0 ? p.v0 + p.t : p.v0 + dv - clearance;
      const int far = side > 0 ? p.v0 + dv + p.t - 1 + clearance : p.v0 - 1;
      if (!AllAre(out, p.along_x, p.u0 - kMargin, p.u0 + len - 1 + kMargin, near, far, WorldCell::kFree)) continue;
      for (int u = p.u0; u < p.u0 + len; ++u) {
        for (int v = 0; v < p.t; ++v) {
          out.Set(Cell(p.along_x, u, p.v0 + v), WorldCell::kFree);
          out.Set(Cell(p.along_x, u, p.v0 + dv + v), WorldCell::kOccupied);
        }
      }
      if (moves) moves->push_back({from, Box(p, dv)});
      ++moved;
      break;
    }
  }
  return out;
}

}  // namespace pslam
