#include "pslam/sim/floorplan.hpp"

#include <array>
#include <utility>

#include "pslam/sim/floorplan_families.hpp"

namespace pslam {
namespace floorplan {

Built Finish(Canvas& canvas, const Pose2D& start, std::string description) {
  return {canvas.Take(), start, std::move(description), canvas.OutlineArea(), canvas.places()};
}

double TargetArea(Stream& s) { return s.Uniform(kFloorPlanMinArea + 250.0, kFloorPlanMaxArea - 100.0); }

}  // namespace floorplan

namespace {

struct FamilyName {
  FloorPlanFamily family;
  const char* name;
  bool repetitive;
};
constexpr std::array<FamilyName, 8> kFamilies = {{{FloorPlanFamily::kOffice, "office", true},
                                                  {FloorPlanFamily::kHotel, "hotel", true},
                                                  {FloorPlanFamily::kHospital, "hospital", true},
                                                  {FloorPlanFamily::kSchool, "school", true},
                                                  {FloorPlanFamily::kMaze, "maze", true},
                                                  {FloorPlanFamily::kIrregularHall, "hall", false},
                                                  {FloorPlanFamily::kOpenPlan, "open", false},
                                                  {FloorPlanFamily::kMixed, "mixed", true}}};

}  // namespace

FloorPlan GenerateFloorPlan(FloorPlanFamily family, std::uint64_t seed) {
  using namespace floorplan;
  // Each family its own stream, so that seed 1 of two families are not the same numbers.
  Stream s(seed * 16 + static_cast<std::uint64_t>(family));
  Built b = [&] {
    switch (family) {
      case FloorPlanFamily::kOffice: return BuildOffice(s);
      case FloorPlanFamily::kHotel: return BuildHotel(s);
      case FloorPlanFamily::kHospital: return BuildHospital(s);
      case FloorPlanFamily::kSchool: return BuildSchool(s);
      case FloorPlanFamily::kMaze: return BuildMaze(s);
      case FloorPlanFamily::kIrregularHall: return BuildIrregularHall(s, seed);
      case FloorPlanFamily::kOpenPlan: return BuildOpenPlan(s);
      case FloorPlanFamily::kMixed: return BuildMixed(s);
    }
    return BuildOffice(s);
  }();
  FloorPlan plan{family, seed, std::string(FloorPlanFamilyName(family)) + "_" + std::to_string(seed), "",
                 std::move(b.world), b.start, b.outline_area_m2, std::move(b.places)};
  plan.description = "generated " + b.description + " (seed " + std::to_string(seed) + ")";
  return plan;
}

const char* FloorPlanFamilyName(FloorPlanFamily family) {
  for (const FamilyName& f : kFamilies) {
    if (f.family == family) return f.name;
  }
  return "unknown";
}

std::optional<FloorPlanFamily> ParseFloorPlanFamily(const std::string& name) {
  for (const FamilyName& f : kFamilies) {
    if (name == f.name) return f.family;
  }
  return std::nullopt;
}

const std::vector<FloorPlanFamily>& AllFloorPlanFamilies() {
  static const std::vector<FloorPlanFamily> all = [] {
    std::vector<FloorPlanFamily> out;
    for (const FamilyName& f : kFamilies) out.push_back(f.family);
    return out;
  }();
  return all;
}

bool IsRepetitiveFamily(FloorPlanFamily family) {
  for (const FamilyName& f : kFamilies) {
    if (f.family == family) return f.repetitive;
  }
  return false;
}

}  // namespace pslam
