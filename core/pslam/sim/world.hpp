#pragma once
// The simulated environment: a dense, fixed-size map of occupied / free / unknown cells on the
// same world-anchored cell lattice as OccupancyGrid (cell (i, j) covers [i*res, (i+1)*res) x ...).
// Dense rather than tiled because the simulator reads it millions of times and never grows it.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

enum class WorldCell : std::uint8_t { kFree, kOccupied, kUnknown };

class World {
 public:
  // A world covering 'bounds' (inclusive cell indices), every cell set to 'fill'.
  World(double resolution, const CellBox& bounds, WorldCell fill);

  // Cells with p > 0.5 are occupied, known cells with p < 0.5 free, the rest unknown.
  static World FromGrid(const OccupancyGrid& grid);

  double resolution() const { return resolution_; }
  const CellBox& bounds() const { return bounds_; }
  // The area the cells cover, in metres.
  Eigen::AlignedBox2d Extent() const {
    return {bounds_.min.cast<double>() * resolution_,
            (bounds_.max.cast<double>() + Eigen::Vector2d::Ones()) * resolution_};
  }

  Eigen::Vector2i WorldToCell(const Eigen::Vector2d& p) const {
    return {static_cast<int>(std::floor(p.x() / resolution_)), static_cast<int>(std::floor(p.y() / resolution_))};
  }
  Eigen::Vector2d CellCenter(const Eigen::Vector2i& c) const {
    return {(c.x() + 0.5) * resolution_, (c.y() + 0.5) * resolution_};
  }

  bool Contains(const Eigen::Vector2i& c) const { return bounds_.Contains(c); }
  // Cells outside the bounds are unknown.
  WorldCell At(const Eigen::Vector2i& c) const { return Contains(c) ? cells_[Index(c)] : WorldCell::kUnknown; }
  bool IsOccupied(const Eigen::Vector2i& c) const { return At(c) == WorldCell::kOccupied; }
  bool IsFree(const Eigen::Vector2i& c) const { return At(c) == WorldCell::kFree; }
  // Writes inside the bounds only; cells outside are ignored, so painters need not clip.
  void Set(const Eigen::Vector2i& c, WorldCell value) {
    if (Contains(c)) cells_[Index(c)] = value;
  }

  // True when a disc of 'radius' at 'centre' overlaps only free cells. Unknown cells count as
  // blocked: the robot must not drive where the world says nothing.
  bool IsDiscFree(const Eigen::Vector2d& centre, double radius) const;

  std::size_t Count(WorldCell value) const;

  // An OccupancyGrid holding exactly these cells (with LoadMap's probabilities), for SaveMap.
  OccupancyGrid ToGrid() const;

 private:
  std::size_t Index(const Eigen::Vector2i& c) const { return bounds_.Index(c); }

  double resolution_;
  CellBox bounds_;
  std::vector<WorldCell> cells_;
};

// Loads a map_server YAML (+ PGM/PNG) through LoadMap. Throws std::runtime_error like LoadMap.
World LoadWorld(const std::string& yaml_path);

}  // namespace pslam
