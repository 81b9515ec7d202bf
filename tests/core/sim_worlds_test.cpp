// The shipped worlds in core/worlds/: they load, their start poses are free, they still match the
// generator, and they have the geometry the paper gives.
//
// To regenerate the committed files after changing the generator:
//   PSLAM_REGENERATE_WORLDS=1 core_tests --gtest_filter='SimWorldsTest.CommittedFilesMatchTheGenerator'
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <queue>
#include <string>
#include <vector>

#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/world.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

namespace fs = std::filesystem;

constexpr double kRes = kShippedWorldResolution;

fs::path WorldsDir() { return fs::path(__FILE__).parent_path().parent_path().parent_path() / "core" / "worlds"; }
std::string Yaml(const std::string& name) { return (WorldsDir() / (name + ".yaml")).string(); }

// Lengths of the runs of equal cells along a row (horizontal) or column, over [from, to) cells.
std::vector<std::pair<WorldCell, int>> Runs(const World& w, int fixed, int from, int to, bool horizontal) {
  std::vector<std::pair<WorldCell, int>> runs;
  for (int i = from; i < to; ++i) {
    const WorldCell c = w.At(horizontal ? Eigen::Vector2i(i, fixed) : Eigen::Vector2i(fixed, i));
    if (runs.empty() || runs.back().first != c) runs.push_back({c, 0});
    ++runs.back().second;
  }
  return runs;
}

// The free cells reachable from 'from' through free 4-neighbours.
struct Reachable {
  const World* world;
  std::vector<bool> seen;  // row-major over the world's bounds
  std::size_t count = 0;
  bool Has(const Eigen::Vector2d& p) const {
    const Eigen::Vector2i c = world->WorldToCell(p);
    return world->Contains(c) && seen[Index(c)];
  }
  std::size_t Index(const Eigen::Vector2i& c) const {
    const CellBox& b = world->bounds();
    return static_cast<std::size_t>(c.y() - b.min.y()) * static_cast<std::size_t>(b.width()) +
           static_cast<std::size_t>(c.x() - b.min.x());
  }
};

Reachable FreeReachable(const World& world, const Eigen::Vector2d& from) {
  const CellBox& b = world.bounds();
  Reachable r{&world, std::vector<bool>(static_cast<std::size_t>(b.width()) * static_cast<std::size_t>(b.height()))};
  std::vector<Eigen::Vector2i> stack;
  const auto visit = [&](const Eigen::Vector2i& c) {
    if (!world.IsFree(c) || r.seen[r.Index(c)]) return;  // IsFree is false outside the bounds
    r.seen[r.Index(c)] = true;
    ++r.count;
    stack.push_back(c);
  };
  visit(world.WorldToCell(from));
  while (!stack.empty()) {
    const Eigen::Vector2i c = stack.back();
    stack.pop_back();
    for (const Eigen::Vector2i& d : {Eigen::Vector2i(1, 0), Eigen::Vector2i(-1, 0), Eigen::Vector2i(0, 1),
                                    Eigen::Vector2i(0, -1)}) {
      visit(c + d);
    }
  }
  return r;
}

TEST(SimWorldsTest, CommittedFilesMatchTheGenerator) {
  if (std::getenv("PSLAM_REGENERATE_WORLDS") != nullptr) WriteShippedWorlds(WorldsDir().string());
  for (const ShippedWorld& expected : MakeShippedWorlds()) {
    SCOPED_TRACE(expected.name);
    const World loaded = LoadWorld(Yaml(expected.name));
    ASSERT_EQ(loaded.bounds().min, expected.world.bounds().min);
    ASSERT_EQ(loaded.bounds().max, expected.world.bounds().max);
    int differing = 0;
    const CellBox& b = loaded.bounds();
    for (int y = b.min.y(); y <= b.max.y(); ++y) {
      for (int x = b.min.x(); x <= b.max.x(); ++x) differing += loaded.At({x, y}) != expected.world.At({x, y});
    }
    EXPECT_EQ(differing, 0) << "core/worlds is stale: regenerate it (see the top of this file)";
    const auto start = ReadStartPose(Yaml(expected.name));
    ASSERT_TRUE(start.has_value());
    EXPECT_NEAR(start->x, expected.start.x, 1e-6);
    EXPECT_NEAR(start->y, expected.start.y, 1e-6);
    EXPECT_NEAR(start->theta, expected.start.theta, 1e-6);
  }
}

TEST(SimWorldsTest, ShippedWorldsLoadWithFreeStartPosesAndSmallImages) {
  for (const std::string name : {"maze", "office", "irregular"}) {
    SCOPED_TRACE(name);
    const World world = LoadWorld(Yaml(name));
    const auto start = ReadStartPose(Yaml(name));
    ASSERT_TRUE(start.has_value());
    EXPECT_TRUE(world.IsDiscFree(start->translation(), 0.25 + 0.1));
    EXPECT_DOUBLE_EQ(world.resolution(), kRes);
    EXPECT_LT(fs::file_size(WorldsDir() / (name + ".pgm")), 1u << 20);
    EXPECT_FALSE(fs::exists(WorldsDir() / (name + ".png")));
  }
}

TEST(SimWorldsTest, MazeHasTheSquaresAndCorridorsOfThePaper) {
  const World maze = LoadWorld(Yaml("maze"));
  const int size = static_cast<int>(std::lround(25.0 / kRes));     // 500 cells inside the walls
  const int obstacle = static_cast<int>(std::lround(3.5 / kRes));  // 70
  const int corridor = static_cast<int>(std::lround(2.2 / kRes));  // 44
  // Through the middle of each row and column of squares: corridor, square, ..., corridor.
  for (int k = 0; k < 4; ++k) {
    const int middle = corridor + k * (obstacle + corridor) + obstacle / 2;
    for (const bool horizontal : {true, false}) {
      const auto runs = Runs(maze, middle, 0, size, horizontal);
      ASSERT_EQ(runs.size(), 9u);
      for (std::size_t i = 0; i < runs.size(); ++i) {
        EXPECT_EQ(runs[i].first, i % 2 == 0 ? WorldCell::kFree : WorldCell::kOccupied);
        EXPECT_EQ(runs[i].second, i % 2 == 0 ? corridor : obstacle);
      }
    }
  }
  // Through a corridor: free from wall to wall, walls on both ends.
  const auto corridor_runs = Runs(maze, corridor / 2, -1, size + 1, true);
  ASSERT_EQ(corridor_runs.size(), 3u);
  EXPECT_EQ(corridor_runs[1].second, size);
  EXPECT_EQ(corridor_runs[0].first, WorldCell::kOccupied);
  // 625 m^2 minus 16 squares of 12.25 m^2.
  EXPECT_NEAR(static_cast<double>(maze.Count(WorldCell::kFree)) * kRes * kRes, 625.0 - 16 * 12.25, 1e-6);
}

TEST(SimWorldsTest, OfficeRoomsRepeat) {
  const World office = LoadWorld(Yaml("office"));
  const double area = static_cast<double>(office.Count(WorldCell::kFree)) * kRes * kRes;
  EXPECT_GT(area, 1800.0);  // about 2000 m^2 of floor, less walls and desks
  EXPECT_LT(area, 2048.0);
  // Each suite equals its neighbour shifted by one bay (6.2 m = 124 cells), on both sides of the
  // corridor (the first bay lacks the wall on its left: the outer wall takes its place).
  const int bay = 124;
  for (const int y0 : {0, 340}) {
    int differing = 0;
    for (int y = y0; y < y0 + 300; ++y) {
      for (int x = bay; x < 3 * bay; ++x) differing += office.At({x, y}) != office.At({x + bay, y});
    }
    EXPECT_EQ(differing, 0);
  }
}

TEST(SimWorldsTest, IrregularWorldIsConnected) {
  const World world = LoadWorld(Yaml("irregular"));
  const auto start = ReadStartPose(Yaml("irregular"));
  ASSERT_TRUE(start.has_value());
  EXPECT_EQ(FreeReachable(world, start->translation()).count, world.Count(WorldCell::kFree));
  // Obstacles take a real share of the room.
  const double occupied_inside = static_cast<double>(world.Count(WorldCell::kOccupied)) * kRes * kRes - 4 * 25.15 * 0.15;
  EXPECT_GT(occupied_inside, 20.0);
}

TEST(SimWorldsTest, ReadStartPoseRejectsMalformedLines) {
  const fs::path dir = fs::path(::testing::TempDir()) / "pslam_sim_start_pose";
  fs::create_directories(dir);
  const auto write = [&](const std::string& text) {
    std::ofstream(dir / "w.yaml") << text;
    return (dir / "w.yaml").string();
  };
  EXPECT_FALSE(ReadStartPose((dir / "missing.yaml").string()).has_value());
  EXPECT_FALSE(ReadStartPose(write("image: w.pgm\n")).has_value());
  EXPECT_FALSE(ReadStartPose(write("# start: 1, 2\n")).has_value());
  EXPECT_FALSE(ReadStartPose(write("# start: 1, x, 2\n")).has_value());
  const auto pose = ReadStartPose(write("image: w.pgm\n  # start: 1.5, -2, 0.25  \n"));
  ASSERT_TRUE(pose.has_value());
  EXPECT_DOUBLE_EQ(pose->x, 1.5);
  EXPECT_DOUBLE_EQ(pose->y, -2.0);
  EXPECT_DOUBLE_EQ(pose->theta, 0.25);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pslam
