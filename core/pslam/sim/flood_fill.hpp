#pragma once
// The cells of a world connected to a start cell through 4-neighbours that pass a test: reachable
// free space (coverage counts only that), or the cells a robot's footprint can reach.
#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

#include "pslam/sim/world.hpp"

namespace pslam {

// Index of cell 'c' (inside world.bounds()) in a row-major mask over the bounds.
std::size_t BoundsIndex(const World& world, const Eigen::Vector2i& c);

// A row-major mask over world.bounds(): true where the cell is 4-connected to 'start' through
// cells inside the bounds for which 'passable' holds ('start' included if it passes).
std::vector<bool> FloodFill4(const World& world, const Eigen::Vector2i& start,
                             const std::function<bool(const Eigen::Vector2i&)>& passable);

}  // namespace pslam
