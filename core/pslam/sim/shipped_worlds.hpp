#pragma once
// The worlds of the paper's simulations (Sec. V-A), rebuilt from their published dimensions, plus
// an irregular control world and a long repetitive office, generated here and committed under
// core/worlds/ (YAML + PGM). The generator is the source of truth; a test checks the committed
// files still match it.
#include <cstdint>
#include <string>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

inline constexpr double kShippedWorldResolution = 0.05;  // m per cell

struct ShippedWorld {
  std::string name;         // file stem: core/worlds/<name>.yaml
  std::string description;  // one line, written into the YAML as "# world: ..."
  World world;
  Pose2D start;             // free start pose, written into the YAML as "# start: ..."
};

// The symmetric square maze of Fig. 7(a): square obstacles separated by corridors, the grid of
// squares centred in the outer walls. Interior spans [0, size] x [0, size].
struct MazeLayout {
  double size = 25.0;             // m, inside the outer walls
  double obstacle_width = 3.5;    // m
  double corridor_width = 2.2;    // m
  double wall_thickness = 0.15;   // m, outer walls (outside the interior)
};
ShippedWorld MakeMazeWorld(const MazeLayout& layout = {});

// A regular office floor in the spirit of Fig. 8: a central corridor along x, a cross corridor
// along y in the middle, and identical two-room suites on both sides of the central corridor
// (front office with a door to the corridor, back office behind it through an inner door, a desk
// in each front office). Repetition is deliberate: it is what the structure predictor exploits.
// Interior spans [0, length] x [0, width].
struct OfficeLayout {
  double length = 64.0;              // m, along the central corridor
  double width = 32.0;               // m
  double corridor_width = 2.0;       // m, both corridors
  int suites_per_wing_side = 5;      // per side of the central corridor, on each side of the cross corridor
  double front_room_depth = 7.0;     // m, from the corridor wall
  double door_width = 1.0;           // m
  double interior_wall_thickness = 0.1;  // m
  double outer_wall_thickness = 0.2;     // m
};
ShippedWorld MakeOfficeWorld(const OfficeLayout& layout = {});

// A room with no repeated structure: seeded random convex polygons and walls at odd angles, each
// kept at least 'min_gap' from every other obstacle, the outer walls and the start, so the free
// space stays connected and the robot fits everywhere. Interior spans [0, size] x [0, size].
// Obstacles that find no room after a bounded number of tries are left out (the description in
// the YAML gives the counts placed).
struct IrregularLayout {
  double size = 25.0;
  double wall_thickness = 0.15;
  int polygon_count = 16;
  int wall_count = 8;
  double min_gap = 1.0;              // m between obstacles
  std::uint64_t seed = 2007;
};
ShippedWorld MakeIrregularWorld(const IrregularLayout& layout = {});

// A long office where almost everything repeats: two parallel corridors along x, joined at both
// ends by short cross corridors so that they form one loop around a block of rooms, and identical
// rooms in four rows: one on the outer side of each corridor and two back to back in the block.
// Each room has one door to its corridor and a desk. Long stretches that look alike and a loop to
// close are what a filter and the structure predictor find hardest. Interior spans
// [0, length] x [0, width], both following from the room sizes (40.1 m x 30.1 m by default).
struct RepetitiveOfficeLayout {
  int rooms_per_row = 8;
  double room_width = 4.4;               // m, inside the walls, along the corridor
  double room_depth = 6.4;               // m, inside the walls
  double corridor_width = 2.0;           // m, all four corridors
  double door_width = 1.0;               // m
  double interior_wall_thickness = 0.1;  // m
  double outer_wall_thickness = 0.2;     // m
};
ShippedWorld MakeRepetitiveOfficeWorld(const RepetitiveOfficeLayout& layout = {});

// maze, office, irregular and repetitive_office with default layouts.
std::vector<ShippedWorld> MakeShippedWorlds();

// Writes <dir>/<name>.yaml and <dir>/<name>.pgm for every shipped world; the folder must exist.
// Throws std::runtime_error naming the file when one cannot be written.
void WriteShippedWorlds(const std::string& dir);

}  // namespace pslam
