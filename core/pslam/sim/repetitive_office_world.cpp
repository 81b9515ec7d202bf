// The repetitive office of shipped_worlds.hpp. Coordinates are multiples of the 5 cm resolution for
// the default layout, so every wall is exactly as thick and every door exactly as wide as specified.
#include <algorithm>
#include <cstdio>
#include <utility>

#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

using Vec = Eigen::Vector2d;

// One row of rooms: the rooms' inside spans [lo, hi] in y; the door wall lies on the corridor's
// side, just above 'hi' (door_up) or just below 'lo'.
struct RoomRow {
  double lo, hi;
  bool door_up;
};

// A row of identical rooms between x = 'x0' (the first room's left wall) and its last wall: the
// walls between rooms and at both ends, the door wall with one door per room, and a desk in each
// room, 1.5 m from its back wall. Rooms in rows with the door below are mirror images in y.
void DrawRow(World& world, const RepetitiveOfficeLayout& o, double x0, const RoomRow& row) {
  const double t = o.interior_wall_thickness, pitch = o.room_width + t;
  const double x1 = x0 + o.rooms_per_row * pitch + t;
  const double door_lo = row.door_up ? row.hi : row.lo - t;
  FillBox(world, Vec(x0, door_lo), Vec(x1, door_lo + t), WorldCell::kOccupied);
  for (int k = 0; k <= o.rooms_per_row; ++k) {
    FillBox(world, Vec(x0 + k * pitch, row.lo), Vec(x0 + k * pitch + t, row.hi), WorldCell::kOccupied);
  }
  const double back = row.door_up ? row.lo : row.hi, into = row.door_up ? 1.0 : -1.0;
  const double desk_near = back + into * 1.5, desk_far = back + into * 2.3;
  for (int k = 0; k < o.rooms_per_row; ++k) {
    const double room_x0 = x0 + k * pitch + t;
    // The door sits 1 m from the room's left wall; the 1.6 m x 0.8 m desk leaves 1.8 m on its left, 1 m on its right.
    FillBox(world, Vec(room_x0 + 1.0, door_lo), Vec(room_x0 + 1.0 + o.door_width, door_lo + t), WorldCell::kFree);
    FillBox(world, Vec(room_x0 + 1.8, std::min(desk_near, desk_far)), Vec(room_x0 + 3.4, std::max(desk_near, desk_far)),
            WorldCell::kOccupied);
  }
}

}  // namespace

ShippedWorld MakeRepetitiveOfficeWorld(const RepetitiveOfficeLayout& o) {
  const double t = o.interior_wall_thickness, c = o.corridor_width, d = o.room_depth;
  const double length = 2.0 * c + o.rooms_per_row * (o.room_width + t) + t;
  const double width = 4.0 * d + 5.0 * t + 2.0 * c;
  World world = MakeWalledRoom(length, width, o.outer_wall_thickness, kShippedWorldResolution);

  // From south to north: outer rooms, south corridor, the block of two back-to-back rows, north
  // corridor, outer rooms. The corridors run the full length; the block stops a corridor's width
  // short of both ends, which leaves the two cross corridors that close the loop.
  const double south_lo = d + t, north_lo = 3.0 * d + 4.0 * t + c;
  const RoomRow rows[] = {{0.0, d, true},
                          {south_lo + c + t, south_lo + c + t + d, false},
                          {south_lo + c + 2.0 * t + d, north_lo - t, true},
                          {north_lo + c + t, width, false}};
  for (const RoomRow& row : rows) DrawRow(world, o, c, row);
  // The spine between the block's two rows.
  FillBox(world, Vec(c, rows[1].hi), Vec(length - c, rows[2].lo), WorldCell::kOccupied);
  // The outer rows have no cross corridor beside them: solid wall fills their ends.
  for (const auto& [y0, y1] : {std::pair{0.0, south_lo}, std::pair{north_lo + c, width}}) {
    FillBox(world, Vec(0.0, y0), Vec(c, y1), WorldCell::kOccupied);
    FillBox(world, Vec(length - c, y0), Vec(length, y1), WorldCell::kOccupied);
  }

  char description[240];
  std::snprintf(description, sizeof description,
                "repetitive office %g m x %g m: two corridors %g m wide along its length, joined at both ends "
                "into a loop; %d identical rooms %g m x %g m with one %g m door each, in 4 rows",
                length, width, c, 4 * o.rooms_per_row, o.room_width, d, o.door_width);
  // The west end of the south corridor, facing east along it.
  return {"repetitive_office", description, std::move(world), Pose2D(c + 1.0, south_lo + c / 2.0, 0.0)};
}

}  // namespace pslam
