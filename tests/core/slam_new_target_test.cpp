// P-SLAM predicts "only when a new target is selected" (paper Sec. IV-B): replanning toward the
// same frontier moves the target cell a little and must not start another prediction.
#include <gtest/gtest.h>

#include <variant>

#include "pslam/experiment/exploration_run.hpp"
#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/simulator.hpp"

namespace pslam {
namespace {

TEST(PSlamNewTargetTest, OnlyATargetAwayFromTheLastPredictedOneStartsAPrediction) {
  const ShippedWorld maze = MakeMazeWorld();
  PSlamOptions options = DefaultExplorationOptions().slam;
  options.filter.particles = 2;
  options.filter.threads = 1;
  options.filter.initial_pose = maze.start;
  PSlam slam(options);
  Simulator sim(maze.world, maze.start);
  for (const SimulatorEvent& e : sim.Step(0.5).events) {
    if (const auto* scan = std::get_if<LaserScan>(&e.data)) slam.AddScan(*scan);
  }
  ASSERT_FALSE(slam.filter().particles().empty());

  const Eigen::Vector2i first = slam.filter().best().map.WorldToCell(maze.start.translation());
  const int cells_per_metre = static_cast<int>(1.0 / options.filter.resolution);
  slam.SetTarget(first, 1.0);
  slam.FlushPredictions();
  slam.SetTarget(first + Eigen::Vector2i(2 * cells_per_metre, 0), 2.0);  // 2 m on: the same goal
  slam.FlushPredictions();
  EXPECT_EQ(slam.stats().targets, 2);
  EXPECT_EQ(slam.stats().new_targets, 1);

  slam.SetTarget(first + Eigen::Vector2i(3 * cells_per_metre, 0), 3.0);  // 3 m from the predicted one
  slam.FlushPredictions();
  EXPECT_EQ(slam.stats().targets, 3);
  EXPECT_EQ(slam.stats().new_targets, 2);
}

}  // namespace
}  // namespace pslam
