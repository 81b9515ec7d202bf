// Extend mode in the particle filter: every particle starts from a map of an earlier session, and
// what the robot sees now overwrites the areas that changed since, instead of doubling them.
#include <gtest/gtest.h>

#include <memory>
#include <variant>

#include "pslam/filter/rbpf.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {
namespace {

constexpr double kResolution = 0.05;
constexpr int kW = 160, kH = 100;  // an 8 m x 5 m room
const double kDefaultCap = RbpfOptions{}.prior_max_probability;

// The room as it is now (a crate at 4.5 m, 3.5 m) or as it was mapped (a wall stub at y = 3.5 m
// from x = 2.5 m to 4 m, and no crate).
World Room(bool as_mapped) {
  World world(kResolution, CellBox{{-1, -1}, {kW + 1, kH + 1}}, WorldCell::kFree);
  for (int x = -1; x <= kW + 1; ++x) {
    for (int y = -1; y <= kH + 1; ++y) {
      const bool wall = x <= 0 || y <= 0 || x >= kW || y >= kH;
      const bool stub = as_mapped && x >= 50 && x < 80 && y >= 70 && y < 72;
      const bool crate = !as_mapped && x >= 90 && x < 100 && y >= 66 && y < 76;
      if (wall || stub || crate) world.Set({x, y}, WorldCell::kOccupied);
    }
  }
  return world;
}

// The old map, plus a known patch 4 m beyond the east wall that no scan reaches now.
std::shared_ptr<const OccupancyGrid> OldMap() {
  auto map = std::make_shared<OccupancyGrid>(Room(true).ToGrid());
  for (int x = 250; x < 260; ++x) {
    for (int y = 10; y < 20; ++y) map->AddLogOdds(x, y, -2000, -2000, 3500);
  }
  return map;
}

double OccupiedShare(const OccupancyGrid& map, int x0, int x1, int y0, int y1) {
  int occupied = 0, n = 0;
  for (int x = x0; x < x1; ++x) {
    for (int y = y0; y < y1; ++y, ++n) occupied += map.Probability(x, y) > 0.5f;
  }
  return static_cast<double>(occupied) / n;
}

// The share of columns x0..x1-1 with an occupied cell in rows y0..y1-1: a wall face, wherever the
// laser's noise put its endpoints.
double WallColumns(const OccupancyGrid& map, int x0, int x1, int y0, int y1) {
  int walls = 0;
  for (int x = x0; x < x1; ++x) walls += OccupiedShare(map, x, x + 1, y0, y1) > 0.0;
  return static_cast<double>(walls) / (x1 - x0);
}

double FreeShare(const OccupancyGrid& map, int x0, int x1, int y0, int y1) {
  int free = 0, n = 0;
  for (int x = x0; x < x1; ++x) {
    for (int y = y0; y < y1; ++y, ++n) free += map.IsKnown(x, y) && map.Probability(x, y) < 0.5f;
  }
  return static_cast<double>(free) / n;
}

// Drives east along y = 1.5 m, past the stub and the crate, and returns the filter.
std::unique_ptr<Rbpf> DrivePast(double prior_max_probability, double prior_forget_depth = 1.0) {
  const Pose2D start(1.0, 1.5, 0.0);
  Simulator sim(Room(false), start);
  RbpfOptions options;
  options.particles = 8;
  options.threads = 1;
  options.initial_pose = start;
  options.points.max_usable_range = 8.0;
  options.prior_map = OldMap();
  options.prior_max_probability = prior_max_probability;
  options.prior_forget_depth = prior_forget_depth;
  auto filter = std::make_unique<Rbpf>(options);
  sim.SetCommand({0.3, 0.0});
  while (sim.time() < 24.0) {
    for (const SimulatorEvent& e : sim.Step(0.2).events) {
      if (const auto* scan = std::get_if<LaserScan>(&e.data)) filter->AddScan(*scan);
    }
  }
  EXPECT_GT(sim.true_pose().x, 5.5);
  return filter;
}

TEST(RbpfPriorMapTest, AWallThatIsGoneIsOverwrittenAndANewOneAppears) {
  const auto filter = DrivePast(kDefaultCap);
  const OccupancyGrid& map = filter->best().map;
  EXPECT_LT(OccupiedShare(map, 50, 80, 70, 72), 0.1) << "the old wall stub is still in the map";
  EXPECT_GT(WallColumns(map, 90, 100, 65, 68), 0.8) << "the crate's south face is missing";
  EXPECT_GT(WallColumns(map, 20, 140, 99, 102), 0.9) << "the north wall, seen all along, is missing";
}

TEST(RbpfPriorMapTest, WithoutTheCapTheOldWallStays) {
  // The same drive with the prior at full confidence: the stub survives next to what the robot
  // sees, which is what the cap is for.
  // About half its cells stay, against under a tenth with the cap.
  const auto filter = DrivePast(1.0);
  EXPECT_GT(OccupiedShare(filter->best().map, 50, 80, 70, 72), 0.3);
}

TEST(RbpfPriorMapTest, TheOldFloorInsideANewCrateIsForgotten) {
  // The robot sees only the crate's south face; the old map had floor where its inside is now.
  const OccupancyGrid& map = DrivePast(kDefaultCap)->best().map;
  EXPECT_LT(FreeShare(map, 92, 98, 69, 75), 0.1) << "the crate's inside is still the old floor";
  EXPECT_GT(FreeShare(map, 60, 85, 40, 60), 0.9) << "floor the robot saw was lost";
  EXPECT_GT(FreeShare(map, 250, 260, 10, 20), 0.99) << "old floor far from anything new was lost";
  // Kept with a depth of 0, as before.
  EXPECT_GT(FreeShare(DrivePast(kDefaultCap, 0.0)->best().map, 92, 98, 69, 75), 0.9);
}

TEST(RbpfPriorMapTest, ParticlesShareThePriorsUntouchedTiles) {
  const auto filter = DrivePast(kDefaultCap);
  const OccupancyGrid& first = filter->particles().front().map;
  const int tx = 250 >> OccupancyGrid::kTileBits, ty = 10 >> OccupancyGrid::kTileBits;
  ASSERT_NE(first.TileAt(tx, ty), nullptr);
  EXPECT_LT(first.Probability(255, 15), 0.5f);
  for (const Particle& p : filter->particles()) EXPECT_EQ(p.map.TileAt(tx, ty), first.TileAt(tx, ty));
}

TEST(RbpfPriorMapTest, APriorOfAnotherResolutionIsRefused) {
  RbpfOptions options;
  options.prior_map = std::make_shared<OccupancyGrid>(0.1);
  EXPECT_THROW(Rbpf{options}, std::invalid_argument);
}

}  // namespace
}  // namespace pslam
