// The hit-ratio recovery of P-SLAM (paper Sec. IV-C, eq. 23) on the particle filter P-SLAM runs:
// a hypothesis that contradicts what the laser sees must not weigh the particles when recovery
// is on, and does when it is off; a right hypothesis is used either way.
#include <gtest/gtest.h>

#include <functional>
#include <variant>
#include <vector>

#include "pslam/filter/rbpf.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {
namespace {

constexpr double kResolution = 0.05;

// A corridor 20 m long and 4 m wide, x in [0, 20], y in [0, 4], with 0.5 m x 0.3 m bays along
// both walls every 1.5 m: a bare corridor gives scan matching nothing to hold on to along it.
World Corridor() {
  const int length = static_cast<int>(20.0 / kResolution), width = static_cast<int>(4.0 / kResolution);
  World world(kResolution, CellBox{{-1, -1}, {length + 1, width + 1}}, WorldCell::kFree);
  for (int x = -1; x <= length + 1; ++x) {
    for (int y = -1; y <= width + 1; ++y) {
      if (x <= 0 || y <= 0 || x >= length || y >= width) world.Set({x, y}, WorldCell::kOccupied);
    }
  }
  for (int start = 5; start < length; start += 30) {
    for (int x = start; x < start + 10; ++x) {
      for (int d = 1; d <= 6; ++d) {
        world.Set({x, d}, WorldCell::kOccupied);
        world.Set({x + 12, width - d}, WorldCell::kOccupied);
      }
    }
  }
  return world;
}

// Predicted cells over x in [3.5, 9] m of the corridor, whose state 'predict' decides.
std::vector<PredictedCell> HypothesisAhead(const World& world, const std::function<bool(const World&, const Eigen::Vector2i&)>& predict) {
  std::vector<PredictedCell> cells;
  for (int x = static_cast<int>(3.5 / kResolution); x <= static_cast<int>(9.0 / kResolution); ++x) {
    for (int y = -1; y <= static_cast<int>(4.0 / kResolution) + 1; ++y) cells.push_back({{x, y}, predict(world, {x, y})});
  }
  return cells;
}

struct UseCounts {
  int with_points = 0;  // updates in which enough endpoints fell inside the hypothesis
  int used = 0;         // ... and the hypothesis entered the weights
};

// The robot starts near the end of the corridor facing that end, so its first scan sees nothing
// beyond x = 1.7 m; the hypothesis is added then. It turns in place toward the corridor, and
// each filter update (every 0.5 rad) sees a new slice of the walls inside the hypothesis. Driving
// along the corridor instead would reveal only a sliver of wall per update, too few endpoints
// (min_hypothesis_points) for the hypothesis to weigh in.
UseCounts Drive(const std::vector<PredictedCell>& hypothesis, bool recovery) {
  const World world = Corridor();
  const Pose2D start(1.5, 2.0, 3.14159);
  Simulator sim(world, start);
  RbpfOptions options;
  options.particles = 8;
  options.threads = 1;
  options.initial_pose = start;
  options.points.max_usable_range = 8.0;
  options.points.no_return_free_range = 7.9;
  options.angular_update = 0.5;
  options.use_predictions = true;
  options.recovery = recovery;
  Rbpf filter(options);
  UseCounts counts;
  bool injected = false;
  sim.SetCommand({0.0, 0.5});
  while (sim.time() < 7.0) {
    for (const SimulatorEvent& e : sim.Step(0.2).events) {
      const auto* scan = std::get_if<LaserScan>(&e.data);
      if (!scan) continue;
      const RbpfStep step = filter.AddScan(*scan);
      if (!injected) {
        filter.AddHypothesis(hypothesis);
        injected = true;
        continue;
      }
      if (!step.updated) continue;
      // Too few endpoints in the hypothesis measure no hit ratio: its zero is not a measurement.
      if (!step.prediction.measured) {
        EXPECT_EQ(step.prediction.best_hit_ratio, 0.0);
      }
      if (step.prediction.hypothesis_points < options.min_hypothesis_points) continue;
      EXPECT_TRUE(step.prediction.measured);
      ++counts.with_points;
      counts.used += step.prediction.used;
    }
  }
  return counts;
}

// Everything predicted free: the walls the laser meets there contradict it (hit ratio 0).
bool AllFree(const World&, const Eigen::Vector2i&) { return false; }
// The true corridor.
bool Truth(const World& world, const Eigen::Vector2i& c) { return world.IsOccupied(c); }

TEST(PSlamRecoveryTest, ContradictedHypothesisIsNotUsedWithRecovery) {
  const UseCounts counts = Drive(HypothesisAhead(Corridor(), AllFree), /*recovery=*/true);
  ASSERT_GE(counts.with_points, 2) << "the laser never reached the hypothesis";
  EXPECT_EQ(counts.used, 0);
}

TEST(PSlamRecoveryTest, ContradictedHypothesisIsUsedWithoutRecovery) {
  const UseCounts counts = Drive(HypothesisAhead(Corridor(), AllFree), /*recovery=*/false);
  ASSERT_GE(counts.with_points, 2);
  EXPECT_EQ(counts.used, counts.with_points);
}

TEST(PSlamRecoveryTest, RightHypothesisIsUsedWithRecovery) {
  const UseCounts counts = Drive(HypothesisAhead(Corridor(), Truth), /*recovery=*/true);
  ASSERT_GE(counts.with_points, 2);
  EXPECT_GT(counts.used, counts.with_points / 2);
}

}  // namespace
}  // namespace pslam
