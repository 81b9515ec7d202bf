// The office floor of shipped_worlds.hpp. Coordinates are multiples of the 5 cm resolution for the
// default layout, so every wall is exactly as thick and every door exactly as wide as specified.
#include <algorithm>
#include <cstdio>
#include <utility>

#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

using Vec = Eigen::Vector2d;

// One suite: a front office (door to the corridor, desk) and a back office behind it. 'x0' is the
// bay's left edge, 'wall_y' the corridor wall's line, 'split_y' the line between front and back,
// 'side' +1 for suites above the corridor and -1 below: suites above are mirror images of those below.
void DrawSuite(World& world, const OfficeLayout& o, double x0, double bay, double wall_y, double split_y, double side) {
  const double t = o.interior_wall_thickness;
  // The corridor wall lies on the room side of 'wall_y'; the split wall is centred on 'split_y'.
  const double wall_lo = side > 0 ? wall_y : wall_y - t;
  const double split_lo = split_y - t / 2;
  // The corridor door sits 1 m from the bay's left edge, the inner door 1 m from its right edge.
  FillBox(world, Vec(x0 + 1.0, wall_lo), Vec(x0 + 1.0 + o.door_width, wall_lo + t), WorldCell::kFree);
  FillBox(world, Vec(x0, split_lo), Vec(x0 + bay, split_lo + t), WorldCell::kOccupied);
  FillBox(world, Vec(x0 + bay - 1.0 - o.door_width, split_lo), Vec(x0 + bay - 1.0, split_lo + t), WorldCell::kFree);
  // A 1.6 m x 0.8 m desk in the front office, 1.5 m from the split wall.
  const double desk_near = split_y - side * 1.5, desk_far = split_y - side * 2.3;
  FillBox(world, Vec(x0 + 0.6, std::min(desk_near, desk_far)), Vec(x0 + 2.2, std::max(desk_near, desk_far)),
          WorldCell::kOccupied);
}

}  // namespace

ShippedWorld MakeOfficeWorld(const OfficeLayout& o) {
  World world = MakeWalledRoom(o.length, o.width, o.outer_wall_thickness, kShippedWorldResolution);
  const double t = o.interior_wall_thickness;
  const double corridor_lo = (o.width - o.corridor_width) / 2.0, corridor_hi = corridor_lo + o.corridor_width;
  const double cross_lo = (o.length - o.corridor_width) / 2.0, cross_hi = cross_lo + o.corridor_width;
  const double wing_length = cross_lo;
  const double bay = wing_length / o.suites_per_wing_side;

  // Walls of both corridors, on the rooms' side so the corridors keep their full width.
  for (const double wing_x0 : {0.0, cross_hi}) {
    FillBox(world, Vec(wing_x0, corridor_lo - t), Vec(wing_x0 + wing_length, corridor_lo), WorldCell::kOccupied);
    FillBox(world, Vec(wing_x0, corridor_hi), Vec(wing_x0 + wing_length, corridor_hi + t), WorldCell::kOccupied);
  }
  for (const auto& [y0, y1] : {std::pair{0.0, corridor_lo}, std::pair{corridor_hi, o.width}}) {
    FillBox(world, Vec(cross_lo - t, y0), Vec(cross_lo, y1), WorldCell::kOccupied);
    FillBox(world, Vec(cross_hi, y0), Vec(cross_hi + t, y1), WorldCell::kOccupied);
  }

  for (const double wing_x0 : {0.0, cross_hi}) {
    for (int k = 0; k < o.suites_per_wing_side; ++k) {
      const double x0 = wing_x0 + k * bay;
      if (k > 0) {  // the wall between this bay and the previous one, centred on the bay edge
        FillBox(world, Vec(x0 - t / 2, 0.0), Vec(x0 + t / 2, corridor_lo), WorldCell::kOccupied);
        FillBox(world, Vec(x0 - t / 2, corridor_hi), Vec(x0 + t / 2, o.width), WorldCell::kOccupied);
      }
      DrawSuite(world, o, x0, bay, corridor_lo, corridor_lo - o.front_room_depth, -1.0);
      DrawSuite(world, o, x0, bay, corridor_hi, corridor_hi + o.front_room_depth, +1.0);
    }
  }

  char description[240];
  std::snprintf(description, sizeof description,
                "office floor %g m x %g m: central and cross corridors %g m wide, %d identical two-room suites "
                "%g m wide on each side of each wing, doors %g m",
                o.length, o.width, o.corridor_width, o.suites_per_wing_side, bay, o.door_width);
  // The west end of the central corridor, facing east along it.
  return {"office", description, std::move(world), Pose2D(2.0, (corridor_lo + corridor_hi) / 2.0, 0.0)};
}

}  // namespace pslam
