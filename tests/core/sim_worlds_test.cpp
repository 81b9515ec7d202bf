// The shipped worlds in core/worlds/: they load, their start poses are free, they still match the
// generator, and they have the geometry they are built to (the paper's, for the maze and the office).
//
// To regenerate the committed files after changing the generator:
//   PSLAM_REGENERATE_WORLDS=1 core_tests --gtest_filter='SimWorldsTest.CommittedFilesMatchTheGenerator'
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <queue>
#include <string>
#include <vector>

#include "pslam/sim/flood_fill.hpp"
#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/world.hpp"
#include "pslam/sim/world_file.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

namespace fs = std::filesystem;

constexpr double kRes = kShippedWorldResolution;

fs::path WorldsDir() { return fs::path(PSLAM_SOURCE_DIR) / "core" / "worlds"; }
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
    return world->Contains(c) && seen[BoundsIndex(*world, c)];
  }
};

Reachable FreeReachable(const World& world, const Eigen::Vector2d& from) {
  const auto free = [&world](const Eigen::Vector2i& c) { return world.IsFree(c); };
  Reachable r{&world, FloodFill4(world, world.WorldToCell(from), free)};
  r.count = static_cast<std::size_t>(std::count(r.seen.begin(), r.seen.end(), true));
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
  for (const std::string name : {"maze", "office", "irregular", "repetitive_office"}) {
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

// The repetitive office's rows of rooms, inside the walls (y, m), and the door walls that face the
// corridors; the rooms span x 2.1 + 4.5 k .. 6.5 + 4.5 k, k = 0..7.
constexpr double kRowLo[] = {0.0, 8.6, 15.1, 23.7}, kRowHi[] = {6.4, 15.0, 21.5, 30.1};
constexpr double kDoorWallLo[] = {6.4, 8.5, 21.5, 23.6};

TEST(SimWorldsTest, RepetitiveOfficeRoomsOpenOnlyThroughTheirDoors) {
  const World office = LoadWorld(Yaml("repetitive_office"));
  const Eigen::Vector2d start = ReadStartPose(Yaml("repetitive_office")).value().translation();
  const Reachable open = FreeReachable(office, start);
  EXPECT_EQ(open.count, office.Count(WorldCell::kFree));
  World closed = office;
  for (const double wall_lo : kDoorWallLo) {
    SCOPED_TRACE(wall_lo);
    // Along the door wall from the first room's left wall to the last room's right wall: a 1 m
    // door 1 m from each room's left wall, the rest wall.
    const int row = static_cast<int>(std::lround(wall_lo / kRes));
    const auto runs = Runs(office, row, 40, 762, true);
    ASSERT_EQ(runs.size(), 17u);
    for (std::size_t i = 1; i < runs.size(); i += 2) {
      EXPECT_EQ(runs[i].first, WorldCell::kFree);
      EXPECT_EQ(runs[i].second, 20);
    }
    FillBox(closed, {2.0, wall_lo}, {38.1, wall_lo + 0.1}, WorldCell::kOccupied);
  }
  // With the doors shut, only the corridors are left: two 40.1 m x 2 m, two 2 m x 13.1 m.
  const Reachable shut = FreeReachable(closed, start);
  EXPECT_NEAR(static_cast<double>(shut.count) * kRes * kRes, 2 * 40.1 * 2.0 + 2 * 2.0 * 13.1, 1e-6);
  for (int row = 0; row < 4; ++row) {
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector2d centre(4.3 + 4.5 * k, (kRowLo[row] + kRowHi[row]) / 2.0);
      EXPECT_TRUE(open.Has(centre)) << "room " << k << " of row " << row;
      EXPECT_FALSE(shut.Has(centre)) << "room " << k << " of row " << row;
    }
  }
}

TEST(SimWorldsTest, RepetitiveOfficeCorridorsFormALoop) {
  World office = LoadWorld(Yaml("repetitive_office"));
  const Eigen::Vector2d start = ReadStartPose(Yaml("repetitive_office")).value().translation();
  // Blocking the south corridor halfway leaves the way round through the north corridor ...
  FillBox(office, {20.0, 6.5}, {20.5, 8.5}, WorldCell::kOccupied);
  EXPECT_EQ(FreeReachable(office, start).count, office.Count(WorldCell::kFree));
  // ... and blocking that too cuts the floor in two.
  FillBox(office, {20.0, 21.6}, {20.5, 23.6}, WorldCell::kOccupied);
  const Reachable west = FreeReachable(office, start);
  EXPECT_TRUE(west.Has({4.3, 3.2}));
  EXPECT_FALSE(west.Has({36.0, 3.2}));
  EXPECT_LT(west.count, office.Count(WorldCell::kFree) * 6 / 10);
}

TEST(SimWorldsTest, RepetitiveOfficeRoomsRepeat) {
  const World office = LoadWorld(Yaml("repetitive_office"));
  // 32 rooms of 4.4 m x 6.4 m less a 1.6 m x 0.8 m desk, their doorways, and the corridors.
  const double area = static_cast<double>(office.Count(WorldCell::kFree)) * kRes * kRes;
  EXPECT_NEAR(area, 32 * (4.4 * 6.4 - 1.6 * 0.8) + 32 * 1.0 * 0.1 + 2 * 40.1 * 2.0 + 2 * 2.0 * 13.1, 1e-6);
  const auto differing = [&office](int x0, int x1, int y0, int y1, auto&& other) {
    int count = 0;
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) count += office.At({x, y}) != office.At(other(x, y));
    }
    return count;
  };
  // Every room, in every row, equals its neighbour shifted by one room and wall (4.5 m = 90 cells).
  EXPECT_EQ(differing(42, 42 + 7 * 90, 0, 602, [](int x, int y) { return Eigen::Vector2i(x + 90, y); }), 0);
  // The two rows with the door above are alike, and so are the two with the door below (15.1 m apart) ...
  const auto north = [](int x, int y) { return Eigen::Vector2i(x, y + 302); };
  EXPECT_EQ(differing(40, 762, 0, 130, north), 0);
  EXPECT_EQ(differing(40, 762, 170, 300, north), 0);
  // ... and mirror images of each other across the south corridor (y -> 15 m - y).
  EXPECT_EQ(differing(40, 762, 0, 130, [](int x, int y) { return Eigen::Vector2i(x, 299 - y); }), 0);
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
