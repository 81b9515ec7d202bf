#pragma once
// A world as it might look some weeks later: a few straight pieces of interior wall (partitions,
// cupboards) moved sideways into the room next to them. Deterministic for a seed, so that the
// changed world of an experiment is the same on every machine.
#include <cstdint>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

struct WallMoveOptions {
  int count = 3;                 // pieces to move
  double length = 1.5;           // m, along the wall
  double shift = 1.0;            // m, sideways
  double clearance = 0.7;        // m of free space kept beyond the piece's new place (a passage)
  double keep_away = 1.5;        // m: no piece moves within this of 'keep_free' (the robot's start)
  std::uint64_t seed = 1;
};

struct WallMove {
  CellBox from, to;              // the piece's cells before and after
};

// Interior wall pieces are straight runs of 'length' with free space on both sides all along,
// at most 0.3 m thick; each moves by 'shift' to the side where the target, its clearance and a
// margin around it are free. Fewer than 'count' moves when fewer pieces qualify.
World MoveWalls(const World& world, const Eigen::Vector2d& keep_free, const WallMoveOptions& options,
                std::vector<WallMove>* moves = nullptr);

}  // namespace pslam
