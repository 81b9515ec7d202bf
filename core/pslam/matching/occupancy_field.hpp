#pragma once
// A smooth view of an occupancy grid for gradient-based scan matching: the "occupancy evidence"
// max(0, 2p - 1) of each cell (free and unknown space carry none), bilinearly interpolated. Coarse
// levels take the maximum over 2^k x 2^k blocks of cells, which widens the basin of convergence
// without storing extra maps per particle. On the finest level the field can place each cell's
// evidence where its hits landed (OccupancyGrid::HitOffset) rather than at the cell's centre.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

class OccupancyField {
 public:
  OccupancyField(const OccupancyGrid& grid, int level, bool hit_offsets = false);

  // Interpolated evidence at a world point, and its gradient (per metre).
  float Value(const Eigen::Vector2f& world, Eigen::Vector2f* gradient) const;
  double cell_size() const { return cell_size_; }

 private:
  // Where the hits of four cells landed, in OccupancyGrid::kHitOffsetScale units per cell.
  struct HitOffsets {
    float x[4], y[4];
  };

  float Coarse(int i, int j) const;
  // Evidence of the cells (i, j), (i+1, j), (i, j+1), (i+1, j+1), and on the finest level where
  // their hits landed when `offset` is given.
  void Corners(int i, int j, float (&value)[4], HitOffsets* offset) const;

  const OccupancyGrid& grid_;
  int level_;
  bool hit_offsets_;
  double cell_size_;
  float per_cell_;  // 1 / cell_size_
  // Coarse levels: pooled cell values read so far, direct-mapped.
  struct PooledSlot {
    std::uint64_t key = 0;
    float value = 0.0f;
    bool filled = false;
  };
  static constexpr std::size_t kPooledSlots = 1024;
  mutable std::vector<PooledSlot> pooled_;
  // Coarse levels: the four values Corners() read last.
  struct LastCorners {
    int i = 0, j = 0;
    float value[4] = {};
    bool filled = false;
  };
  mutable LastCorners last_corners_;
};

// Table lookup of max(0, 2p - 1) for a stored cell value.
float CellEvidence(OccupancyGrid::Cell c);

}  // namespace pslam
