// Driving end to end in the simulator: the server's target path -> pure pursuit -> safety -> the
// simulated Pioneer, with the same agent code that drives the real robot.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <numbers>
#include <thread>

#include "agent.hpp"
#include "common/clock.hpp"
#include "fakes/fake_ingest_server.hpp"
#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/world_file.hpp"
#include "sources/sim_source.hpp"
#include "temp_dir.hpp"
#include "wait_for.hpp"

namespace pslam::agent {
namespace {

using testing::FakeIngestServer;
using testing::StoredMessage;
using testing::TempDir;
using testing::WaitFor;

// Free straight-line distance from the maze's start along its heading, for a 0.26 m disc.
double FreeAhead(const ShippedWorld& w) {
  const Eigen::Vector2d dir(std::cos(w.start.theta), std::sin(w.start.theta));
  double d = 0;
  while (d < 30 && w.world.IsDiscFree(w.start.translation() + d * dir, 0.26)) d += 0.05;
  return d;
}

nlohmann::json Target(const Pose2D& start, const Eigen::Vector2d& goal) {
  return {{"type", "target"},
          {"target", {{"x", goal.x()}, {"y", goal.y()}}},
          {"path", {{start.x, start.y}, {goal.x(), goal.y()}}},
          {"pose", {{"x", start.x}, {"y", start.y}, {"theta", start.theta}}}};
}

std::vector<StoredMessage> Odometry(FakeIngestServer& server) {
  std::vector<StoredMessage> out;
  for (const auto& [id, session] : server.sessions()) {
    for (const auto& m : session.committed) {
      if (m.type == "odom") out.push_back(m);
    }
  }
  return out;
}

// A goal up to 2 m straight ahead of the maze's start, 0.8 m short of what is in front.
Eigen::Vector2d GoalAhead(const ShippedWorld& maze) {
  const Eigen::Vector2d dir(std::cos(maze.start.theta), std::sin(maze.start.theta));
  return maze.start.translation() + std::min(FreeAhead(maze) - 0.8, 2.0) * dir;
}

// Whether the robot's last odometry is within 0.25 m of 'goal'.
bool OdometryReached(FakeIngestServer& server, const Eigen::Vector2d& goal) {
  const auto odom = Odometry(server);
  return !odom.empty() && std::hypot(odom.back().x - goal.x(), odom.back().y - goal.y()) < 0.25;
}

// A 6 m x 3 m walled room, the robot at (1, 1.5) facing the far wall 5 m away: a short run into an
// obstacle. With a post, a 5 cm square at the robot's left shoulder, 0.252 m from its centre
// (the disc is 0.25 m) and behind the laser's plane (0.16 m ahead of the centre): no beam sees it.
// Returns the YAML path.
std::string WriteRoomWorld(const TempDir& dir, bool post = false) {
  World room(0.05, CellBox{{0, 0}, {120, 60}}, WorldCell::kFree);
  if (post) room.Set({20, 35}, WorldCell::kOccupied);  // x 1.00-1.05, y 1.75-1.80
  for (int i = 0; i <= 120; ++i) {
    room.Set({i, 0}, WorldCell::kOccupied);
    room.Set({i, 60}, WorldCell::kOccupied);
  }
  for (int j = 0; j <= 60; ++j) {
    room.Set({0, j}, WorldCell::kOccupied);
    room.Set({120, j}, WorldCell::kOccupied);
  }
  const std::string prefix = (dir.path() / "room").string();
  SaveWorld(room, prefix, Pose2D(1.0, 1.5, 0.0), "test room");
  return prefix + ".yaml";
}

class SimDriveTest : public ::testing::Test {
 protected:
  void StartAgent(double rate, double link_timeout_s = 1.5, std::string world = "") {
    port_ = server_.Start();
    AgentOptions o;
    o.server_host = "127.0.0.1";
    o.server_port = std::to_string(port_);
    o.token = "secret";
    o.spool_dir = (dir_.path() / "spool").string();
    o.status_period_s = 2.0;
    o.safety.link_timeout_s = link_timeout_s;
    SimSourceOptions sim;
    sim.rate = rate;
    sim.scan_rate_hz = 10;
    sim.world = world;
    auto source = std::make_unique<SimSource>(sim);
    source_ = source.get();
    agent_ = std::make_unique<Agent>(o, std::move(source));
    runner_ = std::thread([this] { agent_->Run(stop_); });
    ASSERT_TRUE(WaitFor([&] { return server_.welcomes() >= 1; }, 5.0));
  }
  void StopAgent() {
    stop_ = true;
    if (runner_.joinable()) runner_.join();
  }
  void TearDown() override { StopAgent(); }

  TempDir dir_;
  FakeIngestServer server_;
  unsigned short port_ = 0;
  std::atomic<bool> stop_{false};
  SimSource* source_ = nullptr;  // owned by agent_; read only once the agent has stopped
  std::unique_ptr<Agent> agent_;
  std::thread runner_;
};

TEST_F(SimDriveTest, FollowsTheServersTarget) {
  const ShippedWorld maze = MakeMazeWorld();
  ASSERT_GT(FreeAhead(maze), 1.5);
  const Eigen::Vector2d goal = GoalAhead(maze);
  StartAgent(4.0);
  server_.SendToAll(Target(maze.start, goal));
  ASSERT_TRUE(WaitFor([&] { return OdometryReached(server_, goal); }, 20.0));
  StopAgent();
  EXPECT_EQ(source_->simulator().collision_count(), 0u);
  EXPECT_LT((source_->simulator().true_pose().translation() - goal).norm(), 0.4);
}

TEST_F(SimDriveTest, TurnsOnceInPlaceBeforeFollowingThePath) {
  const ShippedWorld maze = MakeMazeWorld();
  ASSERT_GT(FreeAhead(maze), 1.5);
  const Eigen::Vector2d goal = GoalAhead(maze);
  StartAgent(4.0);
  nlohmann::json look = Target(maze.start, goal);
  look["turn"] = 2.0 * std::numbers::pi;
  server_.SendToAll(look);
  ASSERT_TRUE(WaitFor([&] { return OdometryReached(server_, goal); }, 40.0));
  StopAgent();
  // All the turning happens before the robot leaves its place, and it is one full turn.
  double turned_in_place = 0.0;
  const auto odom = Odometry(server_);
  for (std::size_t i = 1; i < odom.size(); ++i) {
    if (std::hypot(odom[i].x - odom.front().x, odom[i].y - odom.front().y) > 0.05) break;
    turned_in_place += std::abs(std::remainder(odom[i].theta - odom[i - 1].theta, 2.0 * std::numbers::pi));
  }
  EXPECT_GT(turned_in_place, 2.0 * std::numbers::pi - 0.1);
  EXPECT_LT(turned_in_place, 2.0 * std::numbers::pi + 0.5);
  EXPECT_EQ(source_->simulator().collision_count(), 0u);
}

TEST_F(SimDriveTest, StopsBeforeAnObstacleOnThePath) {
  const Pose2D start(1.0, 1.5, 0.0);
  const double wall_x = 6.0;
  StartAgent(4.0, 1.5, WriteRoomWorld(dir_));
  server_.SendToAll(Target(start, {wall_x + 3.0, 1.5}));  // the goal is behind the wall
  // Wait until it has driven and then stood still for a while (odometry keeps coming).
  ASSERT_TRUE(WaitFor(
      [&] {
        const auto odom = Odometry(server_);
        if (odom.size() < 20 || odom.back().x < start.x + 1.0) return false;
        for (std::size_t i = odom.size() - 20; i < odom.size(); ++i) {
          if (std::abs(odom[i].v) > 0.005) return false;
        }
        return true;
      },
      30.0));
  StopAgent();
  const auto& sim = source_->simulator();
  EXPECT_EQ(sim.collision_count(), 0u);
  const double gap = wall_x - sim.true_pose().x;  // centre to the wall's face
  EXPECT_GT(gap, 0.21 + 0.15) << "the front edge came within 15 cm of the wall";
  EXPECT_LT(gap, 1.2) << "stopped far too early";
}

TEST_F(SimDriveTest, BacksOffWhenPinnedAgainstWhatTheLaserCannotSee) {
  // The path bends left at once, so the robot's first arc presses its shoulder on the post: every
  // forward command stalls. Without a recovery it stands there for good.
  const Pose2D start(1.0, 1.5, 0.0);
  StartAgent(4.0, 1.5, WriteRoomWorld(dir_, true));
  server_.SendToAll(Target(start, {1.8, 2.0}));
  ASSERT_TRUE(WaitFor(
      [&] {
        const auto odom = Odometry(server_);
        return !odom.empty() && odom.back().x < start.x - 0.1;
      },
      30.0))
      << "the robot did not back away from the post";
  StopAgent();
  EXPECT_GE(source_->simulator().collision_count(), 1u);
  EXPECT_GE(agent_->stats().stalls, 1);
}

TEST_F(SimDriveTest, LostLinkStopsTheRobot) {
  const ShippedWorld maze = MakeMazeWorld();
  const double free = FreeAhead(maze);
  ASSERT_GT(free, 2.0);
  const Eigen::Vector2d dir(std::cos(maze.start.theta), std::sin(maze.start.theta));
  const Eigen::Vector2d goal = maze.start.translation() + (free - 0.8) * dir;
  StartAgent(1.0, 0.5);
  server_.SendToAll(Target(maze.start, goal));
  ASSERT_TRUE(WaitFor(
      [&] {
        const auto odom = Odometry(server_);
        return !odom.empty() && odom.back().v > 0.15;
      },
      10.0));
  const double killed_at = AgentClock::Now();
  server_.Kill();
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));
  const double restarted_at = AgentClock::Now();
  server_.Start(port_);
  ASSERT_TRUE(WaitFor([&] { return !Odometry(server_).empty() && Odometry(server_).back().t > restarted_at; }, 10.0));
  StopAgent();
  std::size_t checked = 0;
  for (const auto& m : Odometry(server_)) {
    // 0.5 s link timeout + the drive tick + braking from 0.2 m/s at 0.3 m/s^2.
    if (m.t > killed_at + 1.5 && m.t < restarted_at) {
      EXPECT_LT(std::abs(m.v), 0.01) << "at " << m.t - killed_at << " s after the link went down";
      ++checked;
    }
  }
  EXPECT_GT(checked, 10u);  // odometry kept flowing into the spool while the link was down
}

}  // namespace
}  // namespace pslam::agent
