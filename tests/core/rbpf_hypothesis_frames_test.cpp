// The hypothesis model H of eq. 20 on the particle filter: a hypothesis goes into each particle's
// hypothesis map moved by that particle's pose relative to the best one at the time, and comes
// out again by the same move, however far the particles have wandered apart since.
#include <gtest/gtest.h>

#include <variant>
#include <vector>

#include "pslam/filter/rbpf.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {
namespace {

constexpr double kResolution = 0.05;

// A closed room 8 m x 5 m with a pillar, and nothing outside: the laser never sees past its walls.
World Room() {
  const int w = static_cast<int>(8.0 / kResolution), h = static_cast<int>(5.0 / kResolution);
  World world(kResolution, CellBox{{-1, -1}, {w + 1, h + 1}}, WorldCell::kFree);
  for (int x = -1; x <= w + 1; ++x) {
    for (int y = -1; y <= h + 1; ++y) {
      const bool wall = x <= 0 || y <= 0 || x >= w || y >= h;
      const bool pillar = x >= 100 && x < 110 && y >= 40 && y < 50;
      if (wall || pillar) world.Set({x, y}, WorldCell::kOccupied);
    }
  }
  return world;
}

// A predicted block of wall and floor 3 m beyond the room's east wall, where no scan reaches.
std::vector<PredictedCell> BeyondTheEastWall() {
  std::vector<PredictedCell> cells;
  for (int x = 200; x < 230; ++x) {
    for (int y = 20; y < 80; ++y) cells.push_back({{x, y}, x % 10 == 0});
  }
  return cells;
}

std::size_t KnownCells(const OccupancyGrid& grid) {
  const CellBox box = grid.KnownBounds();
  std::size_t n = 0;
  for (int y = box.min.y(); !box.empty() && y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) n += grid.IsKnown(x, y);
  }
  return n;
}

void Drive(Simulator& sim, Rbpf& filter, double seconds) {
  const double until = sim.time() + seconds;
  while (sim.time() < until) {
    for (const SimulatorEvent& e : sim.Step(0.2).events) {
      if (const auto* scan = std::get_if<LaserScan>(&e.data)) filter.AddScan(*scan);
    }
  }
}

TEST(RbpfHypothesisFramesTest, ARemovedHypothesisLeavesNoCellInAnyParticle) {
  const Pose2D start(1.5, 1.5, 0.3);
  Simulator sim(Room(), start);
  RbpfOptions options;
  options.particles = 12;
  options.threads = 1;
  options.initial_pose = start;
  options.points.max_usable_range = 8.0;
  options.motion.translation_per_translation *= 4.0;  // particles spread wide, as on a rough floor
  options.motion.rotation_per_rotation *= 4.0;
  options.resample_threshold = 0.0;  // never resample: each particle keeps its own drift
  Rbpf filter(options);
  sim.SetCommand({0.3, 0.1});
  Drive(sim, filter, 6.0);

  const std::vector<PredictedCell> hypothesis = BeyondTheEastWall();
  const int index = filter.AddHypothesis(hypothesis);
  ASSERT_EQ(index, 0);
  for (const Particle& p : filter.particles()) ASSERT_GT(KnownCells(p.hypothesis), hypothesis.size() / 2);

  sim.SetCommand({0.3, -0.2});
  Drive(sim, filter, 12.0);
  // The particles have moved relative to the best one since: for some of them the move at
  // removal time would land cells elsewhere than the move at adding time put them.
  const Pose2D best_inverse = filter.best().pose.inverse();
  const OccupancyGrid& lattice = filter.best().map;
  int displaced = 0;
  for (const Particle& p : filter.particles()) {
    ASSERT_EQ(p.hypothesis_frames.size(), 1u);
    const Pose2D now = p.pose * best_inverse;
    for (const PredictedCell& c : hypothesis) {
      const Eigen::Vector2d centre = lattice.CellCenter(c.cell);
      displaced += lattice.WorldToCell(now * centre) != lattice.WorldToCell(p.hypothesis_frames[0] * centre);
    }
  }
  ASSERT_GT(displaced, 0) << "the particles kept their places: this test would prove nothing";

  filter.RemoveHypothesis(index, hypothesis);
  for (const Particle& p : filter.particles()) EXPECT_EQ(KnownCells(p.hypothesis), 0u);
}

TEST(RbpfHypothesisFramesTest, NoHypothesisBeforeTheFirstScan) {
  Rbpf filter(RbpfOptions{});
  EXPECT_EQ(filter.AddHypothesis(BeyondTheEastWall()), -1);
  filter.RemoveHypothesis(-1, BeyondTheEastWall());  // a no-op, not a crash
}

}  // namespace
}  // namespace pslam
