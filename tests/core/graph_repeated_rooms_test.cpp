// Loop closure in a repeating building: two identical rooms side by side, each mapped in its own
// submap. Back in one of them, the other submap holds a copy of the robot's surroundings 4.5 m
// away, inside the search window; within that submap alone the copy has no rival.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pslam/graph/loop_closure.hpp"
#include "pslam/sensor/scan_points.hpp"
#include "pslam/sim/laser_model.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

constexpr double kPitch = 4.5;  // metres between the two rooms

// A corridor along y in [0, 3.8] and, north of it, room B (x in [1, 4]) and room A (x in [5.5, 8.5]),
// each 3 x 3.8 m with a 1 m door at the same place. `marked` puts a 1 x 1 m cabinet in a corner
// of room A, so that A and B differ.
World TwoRooms(bool marked) {
  World w = MakeWalledRoom(12.0, 7.8, 0.2, 0.05);
  FillBox(w, {0.0, 3.8}, {2.0, 4.0}, WorldCell::kOccupied);
  FillBox(w, {3.0, 3.8}, {6.5, 4.0}, WorldCell::kOccupied);
  FillBox(w, {7.5, 3.8}, {12.0, 4.0}, WorldCell::kOccupied);
  FillBox(w, {0.0, 4.0}, {1.0, 7.8}, WorldCell::kOccupied);
  FillBox(w, {4.0, 4.0}, {5.5, 7.8}, WorldCell::kOccupied);
  FillBox(w, {8.5, 4.0}, {12.0, 7.8}, WorldCell::kOccupied);
  if (marked) FillBox(w, {7.5, 6.8}, {8.5, 7.8}, WorldCell::kOccupied);
  return w;
}

// Ten nodes turning on the spot at `centre`, so that the submap of the ten sees the whole room.
void TurnAround(const Eigen::Vector2d& centre, double first_heading, std::vector<Pose2D>& path) {
  for (int k = 0; k < 10; ++k) path.emplace_back(centre.x(), centre.y(), NormalizeAngle(first_heading + 0.63 * k));
}

struct Outcome {
  LoopClosureStats stats;
  int kept = 0;    // closure edges in the final graph
  int wrong = 0;   // ... that disagree with the truth by more than 0.3 m
};

// Room B (submap 0), room A (submap 1), the corridor's east end (submap 2), then back in room A.
// Odometry is exact, so any closure that moves a node metres is a wrong one.
Outcome RevisitRoomA(bool marked, bool judge_across_submaps) {
  const World world = TwoRooms(marked);
  std::vector<Pose2D> path;
  TurnAround({2.5, 5.9}, 0.0, path);
  TurnAround({2.5 + kPitch, 5.9}, 0.0, path);
  TurnAround({10.5, 1.9}, 0.0, path);
  TurnAround({2.6 + kPitch, 5.8}, 0.3, path);
  TurnAround({2.4 + kPitch, 6.0}, 0.1, path);

  LoopClosureOptions options;
  options.enabled = true;
  options.nodes_per_submap = 10;
  options.judge_across_submaps = judge_across_submaps;
  options.max_candidates = 8;
  options.base_window = 5.0;  // wide enough to reach the other room
  options.max_window = 5.0;
  LoopCloser closer(options, ScanInsertOptions{}, 0.05);
  std::mt19937_64 rng(11);
  for (std::size_t k = 0; k < path.size(); ++k) {
    closer.AddNode(static_cast<int>(k), path[k], ToScanPoints(SimulateScan(world, path[k], LaserOptions{}, rng), {}));
  }
  closer.Flush();

  Outcome out{closer.stats()};
  for (const PoseGraphEdge& e : closer.graph().edges()) {
    if (e.huber_scale <= 0.0) continue;
    ++out.kept;
    const Pose2D truth = Between(path[static_cast<std::size_t>(e.from)], path[static_cast<std::size_t>(e.to)]);
    if (std::hypot(e.measurement.x - truth.x, e.measurement.y - truth.y) > 0.3) ++out.wrong;
  }
  return out;
}

TEST(LoopCloserRepeatedRoomsTest, ClosesOnTheRightRoomWhenTheCopyScoresLower) {
  // The cabinet makes room B a worse match than room A's own submap, though within room B's submap
  // the copy is the best place and has no rival.
  const Outcome out = RevisitRoomA(true, true);
  EXPECT_GT(out.kept, 0) << "the true closure onto room A's submap is made";
  EXPECT_EQ(out.wrong, 0);
  EXPECT_EQ(out.stats.outliers, 0) << "no wrong closure was accepted and later dropped";
  EXPECT_EQ(out.stats.closures, out.kept);
}

TEST(LoopCloserRepeatedRoomsTest, RefusesAPlaceThatAnotherSubmapHoldsAsWell) {
  // Identical rooms: room A's submap and room B's submap match equally well at places 4.5 m apart.
  // Nothing says which is right, so no closure is made.
  const Outcome out = RevisitRoomA(false, true);
  EXPECT_EQ(out.wrong, 0);
  EXPECT_EQ(out.stats.outliers, 0) << "no wrong closure was accepted and later dropped";
  EXPECT_GT(out.stats.rivalled, 0);
}

TEST(LoopCloserRepeatedRoomsTest, EachSubmapOnItsOwnTakesTheCopyNextDoor) {
  // The rule logs are mapped with: room B's submap closes onto the copy of room A, a wrong closure
  // that the optimiser has to throw out again.
  const Outcome out = RevisitRoomA(true, false);
  EXPECT_GT(out.stats.outliers + out.wrong, 0);
}

}  // namespace
}  // namespace pslam
