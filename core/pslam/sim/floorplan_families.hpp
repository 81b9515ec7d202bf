#pragma once
// One builder per floor-plan family (floorplan.hpp), drawing from the family's seeded stream.
#include <string>
#include <vector>

#include "pslam/sim/floorplan_canvas.hpp"

namespace pslam::floorplan {

struct Built {
  World world;
  Pose2D start;
  std::string description;
  double outline_area_m2 = 0.0;
  std::vector<Vec> places;
};

// Ends a build: takes the canvas's world, area and places.
Built Finish(Canvas& canvas, const Pose2D& start, std::string description);

// The outline area each family aims at, drawn inside [kFloorPlanMinArea, kFloorPlanMaxArea] with
// room to spare for rounding to whole rooms.
double TargetArea(Stream& s);

// Repeated rooms on corridors (floorplan_corridor_families.cpp).
Built BuildOffice(Stream& s);
Built BuildHotel(Stream& s);
Built BuildHospital(Stream& s);
Built BuildSchool(Stream& s);
// Blocks and halls (floorplan_open_families.cpp).
Built BuildMaze(Stream& s);
Built BuildIrregularHall(Stream& s, std::uint64_t seed);
Built BuildOpenPlan(Stream& s);
Built BuildMixed(Stream& s);

}  // namespace pslam::floorplan
