// A short frontier exploration of the paper's square maze: simulator, ground-truth mapping (scans
// inserted at the TRUE pose, no SLAM), target selection, planning and path following together.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <variant>

#include "pslam/explore/explorer.hpp"
#include "pslam/explore/obstacle_stop.hpp"
#include "pslam/explore/path_follower.hpp"
#include "pslam/grid/scan_inserter.hpp"
#include "pslam/sensor/scan_points.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

namespace fs = std::filesystem;

std::string MazeYaml() {
  return (fs::path(PSLAM_SOURCE_DIR) / "core" / "worlds" / "maze.yaml").string();
}

// Fraction of the world's free cells that the built map also reads as free.
double DiscoveredFraction(const World& world, const OccupancyGrid& map) {
  std::size_t free = 0, discovered = 0;
  const CellBox& b = world.bounds();
  for (int y = b.min.y(); y <= b.max.y(); ++y) {
    for (int x = b.min.x(); x <= b.max.x(); ++x) {
      if (!world.IsFree({x, y})) continue;
      ++free;
      discovered += Classify(map, {x, y}, CellClassOptions{}) == CellClass::kFree;
    }
  }
  return static_cast<double>(discovered) / static_cast<double>(free);
}

TEST(ExploreLoopTest, DiscoversThirtyPercentOfTheMazeInBoundedTime) {
  const World world = LoadWorld(MazeYaml());
  const std::optional<Pose2D> start = ReadStartPose(MazeYaml());
  ASSERT_TRUE(start.has_value());
  Simulator sim(world, *start);

  OccupancyGrid map(world.resolution());
  const ScanInserter inserter;
  ScanPointsOptions points;
  points.max_usable_range = 8.0;
  points.no_return_free_range = 7.9;  // nothing within 8 m along a beam without a return: free

  ExploreOptions explore;
  PathFollower follower;
  std::vector<Eigen::Vector2d> blacklist;
  std::optional<LaserScan> last_scan;
  constexpr double kTimeLimit = 300.0;     // simulated seconds
  constexpr double kGoal = 0.30;           // fraction of the free area
  constexpr double kCheckPeriod = 10.0;    // s between coverage checks (each reads the whole map)
  constexpr double kReplanPeriod = 8.0;    // s: fold newly mapped space into the route
  constexpr double kStuckTimeout = 3.0;    // s held by the obstacle stop before giving a target up
  double next_replan = 0.0, stopped_since = -1.0, next_check = kCheckPeriod;
  std::optional<Eigen::Vector2d> target;
  int targets = 0;
  bool done = false;

  while (sim.time() < kTimeLimit && !done) {
    const StepResult step = sim.Step(0.1);
    for (const auto& e : step.events) {
      if (const auto* scan = std::get_if<LaserScan>(&e.data)) {
        inserter.Insert(ToScanPoints(*scan, points), e.true_pose, map);
        last_scan = *scan;
      }
    }
    if (!last_scan) continue;
    if (sim.time() >= next_check) {
      if (DiscoveredFraction(world, map) >= kGoal) break;
      next_check += kCheckPeriod;
    }
    const Pose2D pose = sim.true_pose();

    FollowerOutput out = follower.Update(pose);
    const bool give_up = step.collided || (stopped_since >= 0.0 && sim.time() - stopped_since > kStuckTimeout);
    if (give_up && target) blacklist.push_back(*target);
    if (out.goal_reached || give_up || sim.time() >= next_replan) {
      ExploreRequest request;
      request.robot_position = pose.translation();
      request.blacklist = blacklist;
      const ExploreDecision decision = SelectNextTarget(map, request, explore);
      if (decision.done()) {
        done = true;
        break;
      }
      target = decision.target->position;
      follower.SetPath(decision.target->path);
      next_replan = sim.time() + kReplanPeriod;
      stopped_since = -1.0;
      ++targets;
      out = follower.Update(pose);
    }
    const DriveCommand command = ApplyObstacleStop(out.command, *last_scan);
    if (command.linear < out.command.linear) {
      if (stopped_since < 0.0) stopped_since = sim.time();
    } else {
      stopped_since = -1.0;
    }
    sim.SetCommand({command.linear, command.angular});
  }

  const double discovered = DiscoveredFraction(world, map);
  EXPECT_GE(discovered, kGoal) << "after " << sim.time() << " s and " << targets << " targets";
  EXPECT_GT(targets, 1);
  EXPECT_EQ(sim.collision_count(), 0u);
  std::printf("[ explore ] %.0f %% of the maze's free area in %.0f simulated s, %d targets, %zu given up\n",
              100.0 * discovered, sim.time(), targets, blacklist.size());
}

}  // namespace
}  // namespace pslam
