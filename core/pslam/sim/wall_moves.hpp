#pragma once
// A world as it might look some weeks later: a few straight pieces of interior wall (partitions)
// or free-standing obstacles (furniture, the maze's blocks) moved sideways. Deterministic for a
// seed, so that the changed world of an experiment is the same on every machine.
#include <cstdint>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

struct WallMoveOptions {
  int count = 3;                 // pieces and obstacles to move
  double length = 1.5;           // m, along the wall
  double shift = 1.0;            // m, sideways
  double clearance = 0.7;        // m of free space kept beyond the piece's new place (a passage)
  double keep_away = 1.5;        // m: no piece moves within this of 'keep_free' (the robot's start)
  std::uint64_t seed = 1;
};

struct WallMove {
  CellBox from, to;              // the bounds of the cells moved, before and after
};

// Interior wall pieces are straight runs of 'length' with free space on both sides all along,
// at most 0.3 m thick; free-standing obstacles are occupied components that touch no unknown cell
// (the outer walls do). Each moves by 'shift' to a side where its new place, with 'clearance'
// around it, is free. Fewer than 'count' moves when fewer candidates qualify.
// With 'seen' (a map of the world, e.g. the first session's), only what it shows is moved: at least
// half of a candidate's faces (cells next to free space) are walls there, within one cell.
World MoveWalls(const World& world, const Eigen::Vector2d& keep_free, const WallMoveOptions& options,
                std::vector<WallMove>* moves = nullptr, const OccupancyGrid* seen = nullptr);

}  // namespace pslam
