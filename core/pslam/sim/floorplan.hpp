#pragma once
// Generated floor plans: a population of buildings the predictor was never tuned on, deterministic
// per (family, seed). Families the paper's premise is about (repeated rooms along corridors:
// office, hotel, hospital ward, school, maze) and families it is not (irregular hall, open-plan
// floor) plus a mixed one. Each draws its size (500-3000 m^2 of floor), corridor lengths and
// widths, room sizes, door widths (0.9-1.4 m, passable by the robot) and furniture from the seed;
// "identical" rooms vary a little (furniture moved or missing, a door on the other side, now and
// then a double room). Furniture keeps kFloorPlanGap from walls and other furniture, or stands
// flush against a wall, so every room stays reachable by the robot's inflated footprint.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

enum class FloorPlanFamily { kOffice, kHotel, kHospital, kSchool, kMaze, kIrregularHall, kOpenPlan, kMixed };

inline constexpr double kFloorPlanGap = 0.9;  // m: narrowest passage left between furniture and walls
inline constexpr double kFloorPlanMinArea = 500.0, kFloorPlanMaxArea = 3000.0;  // m^2 of building outline

struct FloorPlan {
  FloorPlanFamily family;
  std::uint64_t seed = 0;
  std::string name;         // "<family>_<seed>", a file stem
  std::string description;  // one line for the YAML's "# world:"
  World world;              // 0.05 m cells; outside the outer walls unknown
  Pose2D start;             // free, in the first corridor (or a corner of a hall), facing along it
  double outline_area_m2 = 0.0;  // inside the outer walls
  // A point just inside each room's door and in each corridor or hall: places the robot must be
  // able to reach from the start (the validity tests check it with the inflated footprint).
  std::vector<Eigen::Vector2d> places;
};

FloorPlan GenerateFloorPlan(FloorPlanFamily family, std::uint64_t seed);

const char* FloorPlanFamilyName(FloorPlanFamily family);  // office, hotel, hospital, school, maze, hall, open, mixed
std::optional<FloorPlanFamily> ParseFloorPlanFamily(const std::string& name);
const std::vector<FloorPlanFamily>& AllFloorPlanFamilies();
// Families built of repeated rooms or blocks: where the predictor should predict (mixed counts).
bool IsRepetitiveFamily(FloorPlanFamily family);

}  // namespace pslam
