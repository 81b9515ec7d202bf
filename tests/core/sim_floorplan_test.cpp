// The floor-plan generator: the same seed gives the same building, and every family's buildings
// are valid worlds for the exploration experiments: size in range, free space in one piece, every
// room and corridor reachable from the start by the robot's inflated footprint (so every door is
// passable), and a start the robot fits at.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "pslam/experiment/exploration_run.hpp"
#include "pslam/explore/distance_transform.hpp"
#include "pslam/explore/path_planner.hpp"
#include "pslam/sim/diff_drive.hpp"
#include "pslam/sim/flood_fill.hpp"
#include "pslam/sim/floorplan.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

// The planner's footprint: the robot's radius plus its inflation margin.
double InflatedRadius() {
  const PlannerOptions planning;
  return planning.robot_radius + planning.inflation_margin;
}

constexpr std::uint64_t kSeeds[] = {1, 2, 3, 4, 5, 6};

TEST(SimFloorPlanTest, SameSeedSameBuildingOtherSeedOtherBuilding) {
  for (const FloorPlanFamily family : AllFloorPlanFamilies()) {
    SCOPED_TRACE(FloorPlanFamilyName(family));
    const FloorPlan a = GenerateFloorPlan(family, 7), b = GenerateFloorPlan(family, 7), c = GenerateFloorPlan(family, 8);
    ASSERT_EQ(a.world.bounds().min, b.world.bounds().min);
    ASSERT_EQ(a.world.bounds().max, b.world.bounds().max);
    int differing = 0;
    const CellBox& box = a.world.bounds();
    for (int y = box.min.y(); y <= box.max.y(); ++y) {
      for (int x = box.min.x(); x <= box.max.x(); ++x) differing += a.world.At({x, y}) != b.world.At({x, y});
    }
    EXPECT_EQ(differing, 0);
    EXPECT_EQ(a.description, b.description);
    EXPECT_NE(a.description, c.description);
  }
}

TEST(SimFloorPlanTest, EveryFamilyIsInSizeConnectedAndPassable) {
  const double radius_cells = InflatedRadius() / 0.05;
  for (const FloorPlanFamily family : AllFloorPlanFamilies()) {
    for (const std::uint64_t seed : kSeeds) {
      const FloorPlan plan = GenerateFloorPlan(family, seed);
      SCOPED_TRACE(plan.name + ": " + plan.description);
      const World& w = plan.world;
      EXPECT_GE(plan.outline_area_m2, kFloorPlanMinArea);
      EXPECT_LE(plan.outline_area_m2, kFloorPlanMaxArea);
      const double free_m2 = static_cast<double>(w.Count(WorldCell::kFree)) * 0.0025;
      EXPECT_GT(free_m2, 0.4 * plan.outline_area_m2);
      EXPECT_LT(free_m2, plan.outline_area_m2);
      EXPECT_TRUE(w.IsDiscFree(plan.start.translation(), DiffDriveOptions{}.robot_radius));

      // Free space in one piece: no pocket the robot could see into but never count.
      const Eigen::Vector2i start = w.WorldToCell(plan.start.translation());
      const std::vector<bool> free = FloodFill4(w, start, [&](const Eigen::Vector2i& c) { return w.IsFree(c); });
      EXPECT_EQ(static_cast<std::size_t>(std::count(free.begin(), free.end(), true)), w.Count(WorldCell::kFree));

      // Where the inflated footprint fits, and which of those cells the robot reaches from the start.
      const int width = w.bounds().width(), height = w.bounds().height();
      std::vector<bool> blocked(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) blocked[BoundsIndex(w, w.bounds().min + Eigen::Vector2i(x, y))] = !w.IsFree(w.bounds().min + Eigen::Vector2i(x, y));
      }
      const std::vector<float> d2 = SquaredDistanceTransform(blocked, width, height);
      const auto fits = [&](const Eigen::Vector2i& c) { return d2[BoundsIndex(w, c)] > radius_cells * radius_cells; };
      const std::vector<bool> reach = FloodFill4(w, start, fits);
      ASSERT_FALSE(plan.places.empty());
      int unreachable = 0;
      for (const Eigen::Vector2d& p : plan.places) {
        const Eigen::Vector2i c = w.WorldToCell(p);
        if (!w.Contains(c) || !reach[BoundsIndex(w, c)]) {
          ++unreachable;
          ADD_FAILURE() << "place (" << p.x() << ", " << p.y() << ") not reachable by the inflated footprint";
          if (unreachable > 3) break;
        }
      }
    }
  }
}

TEST(SimFloorPlanTest, WrittenFilesLoadWithTheirStart) {
  const FloorPlan plan = GenerateFloorPlan(FloorPlanFamily::kHotel, 3);
  const std::string prefix = (std::filesystem::path(testing::TempDir()) / plan.name).string();
  SaveWorld(plan.world, prefix, plan.start, plan.description);
  const World loaded = LoadWorld(prefix + ".yaml");
  EXPECT_EQ(loaded.Count(WorldCell::kFree), plan.world.Count(WorldCell::kFree));
  EXPECT_EQ(loaded.Count(WorldCell::kOccupied), plan.world.Count(WorldCell::kOccupied));
  const auto start = ReadStartPose(prefix + ".yaml");
  ASSERT_TRUE(start.has_value());
  EXPECT_NEAR(start->x, plan.start.x, 1e-6);
  EXPECT_NEAR(start->y, plan.start.y, 1e-6);
}

int RunCli(const std::string& arguments) {
  std::string command = PSLAM_CLI_BINARY;
  command += " " + arguments + " >/dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SimFloorPlanTest, CliWritesTheGeneratedWorldAndRefusesAnUnknownFamily) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "floorplan_cli";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ASSERT_EQ(RunCli("worlds generate --family school --seed 4 --count 2 --out " + (dir / "s").string()), 0);
  for (const std::uint64_t seed : {4, 5}) {
    const std::string yaml = (dir / ("s_" + std::to_string(seed) + ".yaml")).string();
    const FloorPlan plan = GenerateFloorPlan(FloorPlanFamily::kSchool, seed);
    EXPECT_EQ(LoadWorld(yaml).Count(WorldCell::kFree), plan.world.Count(WorldCell::kFree));
    ASSERT_TRUE(ReadStartPose(yaml).has_value());
  }
  EXPECT_EQ(RunCli("worlds generate --family castle --seed 1 --out " + (dir / "c").string()), 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "c.yaml"));
  EXPECT_EQ(RunCli("experiment explore --generated castle --count 2"), 2);
}

TEST(SimFloorPlanTest, ExplorationTimeBudgetGrowsWithTheFreeArea) {
  // 8 s per m² of free floor, at least 2400 s: a large hotel gets the time its rooms take.
  const FloorPlan hotel = GenerateFloorPlan(FloorPlanFamily::kHotel, 24);
  const double free_m2 = static_cast<double>(hotel.world.Count(WorldCell::kFree)) * 0.05 * 0.05;
  EXPECT_GT(free_m2, 1000.0);
  EXPECT_NEAR(ExplorationTimeBudget(hotel.world), 8.0 * free_m2, 1e-6);
  World small(0.05, CellBox{{0, 0}, {99, 99}}, WorldCell::kFree);  // 25 m²
  EXPECT_EQ(ExplorationTimeBudget(small), 2400.0);
}

TEST(SimFloorPlanTest, FamilyNamesRoundTrip) {
  for (const FloorPlanFamily family : AllFloorPlanFamilies()) {
    EXPECT_EQ(ParseFloorPlanFamily(FloorPlanFamilyName(family)), family);
  }
  EXPECT_FALSE(ParseFloorPlanFamily("castle").has_value());
  EXPECT_TRUE(IsRepetitiveFamily(FloorPlanFamily::kHotel));
  EXPECT_FALSE(IsRepetitiveFamily(FloorPlanFamily::kOpenPlan));
}

}  // namespace
}  // namespace pslam
