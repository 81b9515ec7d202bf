// `pslam localize` (the real binary) on a CARMEN log written from the simulator: the trajectory it
// writes follows the true one from a given pose and from none, and bad input ends in a clear error.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pslam/eval/trajectory_io.hpp"
#include "pslam/explore/path_follower.hpp"
#include "pslam/explore/path_planner.hpp"
#include "pslam/explore/planning_grid.hpp"
#include "pslam/io/map_io.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world_file.hpp"
#include "testing/cli_scratch.hpp"

namespace pslam {
namespace {


const std::string kWorld = std::string(PSLAM_SOURCE_DIR) + "/core/worlds/irregular.yaml";

struct SimulatedLog {
  std::string text;
  std::vector<Pose2D> truth;  // one per scan
};

// The robot drives through the irregular room along planned paths to a few goals; every scan
// becomes an FLASER line (laser pose, then raw odometry) at 5 Hz.
SimulatedLog Simulate() {
  const World world = World::FromGrid(LoadMap(kWorld));
  const Pose2D start = ReadStartPose(kWorld).value();
  Simulator sim(world, start);
  const PlanningGrid grid(world.ToGrid(), PlannerOptions{});
  SimulatedLog log;
  std::ostringstream out;
  out.precision(10);
  out << "PARAM robot_front_laser_max 8.0 0 nohost 0\n";
  for (const Eigen::Vector2d& goal : {Eigen::Vector2d(12.5, 3.0), Eigen::Vector2d(22.0, 12.0), Eigen::Vector2d(12.0, 22.0)}) {
    PathFollower follower;
    const PlannedPath path = PlanPath(grid, sim.true_pose().translation(), goal);
    if (path.status != PlanStatus::kFound) continue;
    follower.SetPath(path.waypoints);
    for (bool reached = false; !reached && sim.time() < 600.0;) {
      const FollowerOutput drive = follower.Update(sim.true_pose());
      reached = drive.goal_reached;
      sim.SetCommand({drive.command.linear, drive.command.angular});
      for (const SimulatorEvent& e : sim.Step(0.1).events) {
        const auto* scan = std::get_if<LaserScan>(&e.data);
        if (!scan) continue;
        const Pose2D laser = scan->odometry * scan->sensor_offset;
        out << "FLASER " << scan->ranges.size();
        for (float r : scan->ranges) out << ' ' << r;
        out << ' ' << laser.x << ' ' << laser.y << ' ' << laser.theta << ' ' << scan->odometry.x << ' ' << scan->odometry.y
            << ' ' << scan->odometry.theta << ' ' << 1000.0 + e.time << " nohost " << 1000.0 + e.time << '\n';
        log.truth.push_back(e.true_pose);
      }
    }
  }
  log.text = out.str();
  return log;
}

class LocalizeCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { log_ = new SimulatedLog(Simulate()); }
  static void TearDownTestSuite() { delete log_; }
  void SetUp() override { std::ofstream(scratch_.dir() / "sim.clf") << log_->text; }

  // Exit status of `pslam localize ARGS`, with stdout and stderr kept in files.
  int Run(const std::string& args) { return scratch_.Run("localize", args); }
  std::string Read(const std::string& name) { return scratch_.Read(name); }
  // Position error of the written trajectory at each scan.
  std::vector<double> Errors() {
    const std::vector<StampedPose> poses = ReadTrajectory(scratch_.Path("traj.txt"));
    EXPECT_EQ(poses.size(), log_->truth.size());
    std::vector<double> errors;
    for (std::size_t i = 0; i < poses.size() && i < log_->truth.size(); ++i)
      errors.push_back((poses[i].pose.translation() - log_->truth[i].translation()).norm());
    return errors;
  }

  static SimulatedLog* log_;
  pslam::testing::CliScratch scratch_{"localize-cli"};
};
SimulatedLog* LocalizeCliTest::log_ = nullptr;

TEST_F(LocalizeCliTest, FollowsTheRobotFromAGivenPose) {
  ASSERT_GT(log_->truth.size(), 300u);
  const Pose2D s = ReadStartPose(kWorld).value();
  ASSERT_EQ(Run("--map " + kWorld + " --log " + scratch_.Path("sim.clf") + " --initial-pose " + std::to_string(s.x + 0.2) +
                "," + std::to_string(s.y - 0.1) + "," + std::to_string(s.theta + 0.1) + " --trajectory " +
                scratch_.Path("traj.txt")),
            0)
      << Read("err.txt");
  double sum = 0.0, worst = 0.0;
  for (double e : Errors()) {
    sum += e;
    worst = std::max(worst, e);
  }
  EXPECT_LT(sum / static_cast<double>(log_->truth.size()), 0.1);
  EXPECT_LT(worst, 0.4);
  EXPECT_NE(Read("out.txt").find("at the end        localized"), std::string::npos) << Read("out.txt");
  EXPECT_NE(Read("out.txt").find("CPU per scan"), std::string::npos);
  // The world's own map saw everything the robot sees: nothing is added to it.
  EXPECT_NE(Read("out.txt").find("walls added       0 cells"), std::string::npos) << Read("out.txt");
}

TEST_F(LocalizeCliTest, FindsTheRobotWithoutAPose) {
  ASSERT_EQ(Run("--map " + kWorld + " --log " + scratch_.Path("sim.clf") + " --trajectory " + scratch_.Path("traj.txt")), 0)
      << Read("err.txt");
  const std::vector<double> errors = Errors();
  ASSERT_FALSE(errors.empty());
  for (std::size_t i = errors.size() / 2; i < errors.size(); ++i) ASSERT_LT(errors[i], 0.2) << "scan " << i;
  EXPECT_NE(Read("out.txt").find("global localization"), std::string::npos);
}

TEST_F(LocalizeCliTest, BadInputEndsInAClearError) {
  const std::string log = " --log " + scratch_.Path("sim.clf");
  EXPECT_EQ(Run("--map " + scratch_.Path("missing.yaml") + log), 1);
  EXPECT_NE(Read("err.txt").find("missing.yaml"), std::string::npos) << Read("err.txt");
  EXPECT_EQ(Run("--map " + kWorld + log + " --global --initial-pose 1,2,0"), 2);
  EXPECT_NE(Read("err.txt").find("exclude each other"), std::string::npos);
  EXPECT_EQ(Run("--map " + kWorld + log + " --initial-pose 1,2"), 2);
  EXPECT_EQ(Run("--map " + kWorld + log + " --set min_particles=0"), 2);
  EXPECT_EQ(Run("--map " + kWorld + " --log " + scratch_.Path("none.clf")), 1);
}

}  // namespace
}  // namespace pslam
