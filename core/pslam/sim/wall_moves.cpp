#include "pslam/sim/wall_moves.hpp"

#include <algorithm>
#include <cmath>
#include <random>

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

CellBox Box(const Piece& p, int dv) {
  CellBox box;
  box.Extend(Cell(p.along_x, p.u0, p.v0 + dv));
  box.Extend(Cell(p.along_x, p.u0 + p.len - 1, p.v0 + dv + p.t - 1));
  return box;
}

}  // namespace

World MoveWalls(const World& world, const Eigen::Vector2d& keep_free, const WallMoveOptions& o,
                std::vector<WallMove>* moves) {
  const double res = world.resolution();
  const int len = std::max(4, static_cast<int>(std::lround(o.length / res)));
  const int shift = std::max(1, static_cast<int>(std::lround(o.shift / res)));
  const int clearance = static_cast<int>(std::lround(o.clearance / res));
  std::vector<Piece> pieces = FindPieces(world, true, len);
  const std::vector<Piece> vertical = FindPieces(world, false, len);
  pieces.insert(pieces.end(), vertical.begin(), vertical.end());
  std::mt19937_64 rng(o.seed);
  std::shuffle(pieces.begin(), pieces.end(), rng);

  World out = world;
  int moved = 0;
  for (const Piece& p : pieces) {
    if (moved >= o.count) break;
    const CellBox from = Box(p, 0);
    const Eigen::Vector2d centre = (from.min + from.max).cast<double>() * 0.5 * res;
    if ((centre - keep_free).norm() < o.keep_away + o.shift) continue;
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
