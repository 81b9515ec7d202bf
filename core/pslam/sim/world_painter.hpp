#pragma once
// Drawing primitives for building worlds: boxes, thick segments and polygons, rasterized by cell
// centre (a cell takes the value when its centre lies inside the shape). Used by the shipped-world
// generator and by tests that need a tiny synthetic world.
#include <Eigen/Core>
#include <vector>

#include "pslam/sim/world.hpp"

namespace pslam {

// An empty rectangular room: free interior [0, length] x [0, width] enclosed by occupied walls of
// 'wall_thickness' lying outside it, and nothing beyond the walls.
World MakeWalledRoom(double length, double width, double wall_thickness, double resolution);

// Cells whose centres lie in [min, max) on both axes. Box edges on multiples of the resolution
// therefore give exact sizes: a 3.5 m box at 0.05 m is exactly 70 cells wide.
void FillBox(World& world, const Eigen::Vector2d& min, const Eigen::Vector2d& max, WorldCell value);

// Cells whose centres lie within 'thickness' / 2 of the segment a-b (a wall with round ends).
void FillSegment(World& world, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double thickness, WorldCell value);

// Cells whose centres lie inside the polygon (any simple polygon; even-odd rule).
void FillPolygon(World& world, const std::vector<Eigen::Vector2d>& polygon, WorldCell value);

}  // namespace pslam
