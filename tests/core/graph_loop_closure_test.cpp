// Loop closure: the pose graph, the branch-and-bound search and the whole closer on a loop whose
// odometry alone drifts by metres.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pslam/graph/branch_and_bound_matcher.hpp"
#include "pslam/graph/loop_closure.hpp"
#include "pslam/graph/pose_graph.hpp"
#include "pslam/grid/scan_inserter.hpp"
#include "pslam/sensor/scan_points.hpp"
#include "pslam/sim/laser_model.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

// A 24 x 16 m hall around a 14 x 6 m block, with boxes of different sizes so that no two places
// along the loop look alike.
World LoopWorld() {
  World w = MakeWalledRoom(24.0, 16.0, 0.2, 0.05);
  FillBox(w, {5.0, 5.0}, {19.0, 11.0}, WorldCell::kOccupied);
  FillBox(w, {3.0, 0.0}, {3.6, 0.8}, WorldCell::kOccupied);
  FillBox(w, {11.0, 0.0}, {12.5, 0.5}, WorldCell::kOccupied);
  FillBox(w, {23.2, 7.0}, {24.0, 9.5}, WorldCell::kOccupied);
  FillBox(w, {15.0, 15.0}, {15.4, 16.0}, WorldCell::kOccupied);
  FillBox(w, {6.0, 15.2}, {8.5, 16.0}, WorldCell::kOccupied);
  FillBox(w, {0.0, 9.0}, {0.7, 9.6}, WorldCell::kOccupied);
  FillBox(w, {8.0, 4.2}, {8.6, 5.0}, WorldCell::kOccupied);
  FillBox(w, {16.0, 11.0}, {17.5, 11.4}, WorldCell::kOccupied);
  return w;
}

// Counter-clockwise around the block, then on along the first side past the start: poses 0.25 m
// apart on the straights, 0.2 rad apart when turning on the spot at the corners.
std::vector<Pose2D> LoopPath() {
  const std::vector<Eigen::Vector2d> corners = {{2.5, 2.5}, {21.5, 2.5}, {21.5, 13.5}, {2.5, 13.5}, {2.5, 2.5}, {12.0, 2.5}};
  std::vector<Pose2D> path;
  double heading = 0.0;
  for (std::size_t i = 0; i + 1 < corners.size(); ++i) {
    const Eigen::Vector2d d = corners[i + 1] - corners[i];
    const double target = std::atan2(d.y(), d.x());
    while (!path.empty() && std::abs(NormalizeAngle(target - heading)) > 1e-9) {
      const double turn = std::clamp(NormalizeAngle(target - heading), -0.2, 0.2);
      heading = NormalizeAngle(heading + turn);
      path.emplace_back(corners[i].x(), corners[i].y(), heading);
    }
    heading = target;
    const int steps = static_cast<int>(std::round(d.norm() / 0.25));
    for (int k = path.empty() ? 0 : 1; k <= steps; ++k) {
      const Eigen::Vector2d p = corners[i] + d * (static_cast<double>(k) / steps);
      path.emplace_back(p.x(), p.y(), heading);
    }
  }
  return path;
}

// The same relative motions with a heading bias per metre: what a filter that slowly turns
// would report.
std::vector<Pose2D> Drift(const std::vector<Pose2D>& truth, double radians_per_metre) {
  std::vector<Pose2D> out = {truth.front()};
  for (std::size_t k = 1; k < truth.size(); ++k) {
    Pose2D step = Between(truth[k - 1], truth[k]);
    step = Pose2D(step.x, step.y, step.theta + radians_per_metre * std::hypot(step.x, step.y));
    out.push_back(out.back() * step);
  }
  return out;
}

// Share of a map's occupied cells that lie on (or next to) a wall of the world.
double OnWalls(const OccupancyGrid& map, const World& world) {
  const CellBox box = map.KnownBounds();
  int occupied = 0, on_walls = 0;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      if (map.Probability(x, y) <= 0.5) continue;
      ++occupied;
      bool near = false;
      for (int dy = -1; dy <= 1 && !near; ++dy)
        for (int dx = -1; dx <= 1 && !near; ++dx) near = world.IsOccupied({x + dx, y + dy});
      on_walls += near;
    }
  }
  return occupied ? static_cast<double>(on_walls) / occupied : 0.0;
}

TEST(PoseGraphTest, LoopEdgeRemovesAccumulatedDrift) {
  // A square of side 10 m in 40 steps, measured with a heading bias, closed by one edge that says
  // the last node is the first one.
  PoseGraph graph;
  std::vector<Pose2D> truth;
  for (int side = 0; side < 4; ++side) {
    for (int k = 0; k < 10; ++k) {
      const Pose2D corner = side == 0 ? Pose2D(0, 0, 0) : truth.back() * Pose2D(1.0, 0, 0);
      truth.push_back(k == 0 && side > 0 ? Pose2D(corner.x, corner.y, corner.theta + M_PI / 2) : (truth.empty() ? corner : truth.back() * Pose2D(1.0, 0, 0)));
    }
  }
  const Eigen::Matrix3d info = Eigen::Vector3d(50.0, 50.0, 100.0).asDiagonal();
  graph.AddNode(truth[0]);
  for (std::size_t k = 1; k < truth.size(); ++k) {
    const Pose2D measured = Between(truth[k - 1], truth[k]) * Pose2D(0.0, 0.0, 0.02);
    graph.AddNode(graph.pose(static_cast<int>(k) - 1) * measured);
    graph.AddEdge({static_cast<int>(k) - 1, static_cast<int>(k), measured, info, 0.0});
  }
  const int last = graph.size() - 1;
  const double before = (graph.pose(last).translation() - truth.back().translation()).norm();
  graph.AddEdge({0, last, Between(truth.front(), truth.back()), info, 2.0});
  const PoseGraphSolveSummary summary = graph.Optimize();
  const double after = (graph.pose(last).translation() - truth.back().translation()).norm();
  EXPECT_GT(before, 1.0);
  EXPECT_LT(after, 0.1);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_EQ(graph.pose(0).x, truth[0].x);  // the anchor does not move
}

// The 5 cm grid of the scans simulated at 'poses', their points kept as 'points' says.
OccupancyGrid MapSeenFrom(const World& world, const std::vector<Pose2D>& poses, std::mt19937_64& rng,
                          const ScanPointsOptions& points = {}) {
  OccupancyGrid grid(0.05);
  ScanInserter inserter;
  for (const Pose2D& p : poses) inserter.Insert(ToScanPoints(SimulateScan(world, p, LaserOptions{}, rng), points), p, grid);
  return grid;
}

std::vector<Eigen::Vector2f> HitsAt(const World& world, const Pose2D& pose, std::mt19937_64& rng) {
  return ToScanPoints(SimulateScan(world, pose, LaserOptions{}, rng), {}).hits;
}

TEST(BranchAndBoundMatcherTest, FindsAScanFarFromItsGuess) {
  const World world = LoopWorld();
  std::mt19937_64 rng(3);
  const Pose2D at(21.0, 3.0, 2.0);
  const OccupancyGrid grid = MapSeenFrom(world, {at, at * Pose2D(-0.5, 0.0, 0.0), at * Pose2D(-1.0, 0.0, 0.0)}, rng);
  const std::vector<Eigen::Vector2f> hits = HitsAt(world, at, rng);
  const MaxPoolStack stack(grid, 6);
  const Pose2D guess = at * Pose2D(1.3, -0.9, 0.25);
  const BranchAndBoundResult found = MatchByBranchAndBound(stack, hits, guess, {.linear_window = 2.0, .angular_window = 0.4});
  ASSERT_TRUE(found.found);
  EXPECT_LT(std::hypot(found.pose.x - at.x, found.pose.y - at.y), 0.08);
  EXPECT_LT(std::abs(NormalizeAngle(found.pose.theta - at.theta)), 0.02);
  EXPECT_GT(found.score, 0.7);
  // Excluding the right answer leaves nothing that scores as well.
  const BranchAndBoundResult other = MatchByBranchAndBound(
      stack, hits, guess, {.linear_window = 2.0, .angular_window = 0.4, .min_score = 0.9 * found.score},
      [&](const Pose2D& p) { return std::hypot(p.x - at.x, p.y - at.y) < 0.5; });
  EXPECT_FALSE(other.found);
}

// The mean level-0 value at the points at 'pose', discretised as the search does: the points turned
// about 'guess' and floored to cells, then moved by whole cells.
double FieldScore(const MaxPoolStack& stack, const std::vector<Eigen::Vector2f>& points, const Pose2D& guess, const Pose2D& pose) {
  const double res = stack.resolution();
  const Pose2D turned(guess.x, guess.y, pose.theta);
  const int dx = static_cast<int>(std::lround((pose.x - guess.x) / res)), dy = static_cast<int>(std::lround((pose.y - guess.y) / res));
  int sum = 0;
  for (const Eigen::Vector2f& p : points) {
    const Eigen::Vector2d w = turned * p.cast<double>();
    sum += stack.At(0, static_cast<int>(std::floor(w.x() / res)) + dx, static_cast<int>(std::floor(w.y() / res)) + dy);
  }
  return sum / (255.0 * static_cast<double>(points.size()));
}

// Scores are summed two ways: with bounds checks when some point of the scan lies past the search's
// arrays (they reach 2^depth cells past the grid's known cells on every side), without them
// otherwise. Either way the search is exact and reports the field's own score at its pose.
TEST(BranchAndBoundMatcherTest, ExactInsideTheGridAndPastItsEdge) {
  const World world = LoopWorld();
  std::mt19937_64 rng(5);
  const Pose2D at(3.0, 13.0, -0.7);
  const BranchAndBoundOptions window{.linear_window = 2.0, .angular_window = 0.3, .min_score = 0.3};
  // Past the edge: the grid holds what lies within 3 m of the robot, the scan reaches 8 m.
  const OccupancyGrid near = MapSeenFrom(world, {at}, rng, {.max_usable_range = 3.0});
  const std::vector<Eigen::Vector2f> moved = HitsAt(world, at * Pose2D(0.3, 0.1, 0.05), rng);
  const MaxPoolStack shallow(near, 4), deep(near, 7);
  const BranchAndBoundResult past_shallow = MatchByBranchAndBound(shallow, moved, at, window);
  const BranchAndBoundResult past_deep = MatchByBranchAndBound(deep, moved, at, window);
  ASSERT_TRUE(past_shallow.found);
  ASSERT_TRUE(past_deep.found);
  EXPECT_EQ(past_shallow.score, past_deep.score);
  EXPECT_DOUBLE_EQ(past_shallow.score, FieldScore(shallow, moved, at, past_shallow.pose));
  // Inside: the grid holds everything the scan sees.
  const OccupancyGrid whole = MapSeenFrom(world, {at}, rng);
  const std::vector<Eigen::Vector2f> again = HitsAt(world, at, rng);
  const MaxPoolStack stack(whole, 6);
  const BranchAndBoundResult inside = MatchByBranchAndBound(stack, again, at * Pose2D(0.4, -0.3, 0.1), window);
  ASSERT_TRUE(inside.found);
  EXPECT_LT(std::hypot(inside.pose.x - at.x, inside.pose.y - at.y), 0.1);
  EXPECT_DOUBLE_EQ(inside.score, FieldScore(stack, again, at * Pose2D(0.4, -0.3, 0.1), inside.pose));
}

// Stopping at the first pose above a minimum finds one exactly when a pose that good exists.
TEST(BranchAndBoundMatcherTest, FirstFoundAboveTheMinimumAgreesWithTheBest) {
  const World world = LoopWorld();
  std::mt19937_64 rng(9);
  const Pose2D at(12.0, 2.5, 0.3);
  const MaxPoolStack stack(MapSeenFrom(world, {at}, rng), 6);
  const std::vector<Eigen::Vector2f> hits = HitsAt(world, at, rng);
  BranchAndBoundOptions options{.linear_window = 2.0, .angular_window = 0.3, .min_score = 0.3};
  const BranchAndBoundResult best = MatchByBranchAndBound(stack, hits, at, options);
  ASSERT_TRUE(best.found);
  options.first_above_min_score = true;
  options.min_score = 0.9 * best.score;
  const BranchAndBoundResult first = MatchByBranchAndBound(stack, hits, at, options);
  ASSERT_TRUE(first.found);
  EXPECT_GE(first.score, options.min_score);
  EXPECT_LE(first.score, best.score);
  options.min_score = best.score + 1e-3;
  EXPECT_FALSE(MatchByBranchAndBound(stack, hits, at, options).found);
}

TEST(LoopCloserTest, ClosesALoopWhoseDriftIsMetres) {
  const World world = LoopWorld();
  const std::vector<Pose2D> truth = LoopPath();
  const std::vector<Pose2D> drifted = Drift(truth, 0.005);
  const double drift = (drifted.back().translation() - truth.back().translation()).norm();
  ASSERT_GT(drift, 1.5) << "the test needs a loop that odometry alone does not close";

  std::mt19937_64 rng(7);
  LoopCloser closer(LoopClosureOptions{}, ScanInsertOptions{}, 0.05);
  OccupancyGrid drifted_map(0.05);
  ScanInserter inserter;
  // Like the filter, continue from the corrected pose after each correction.
  Pose2D to_corrected;
  std::optional<LoopClosureCorrection> last;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const ScanPoints points = ToScanPoints(SimulateScan(world, truth[k], LaserOptions{}, rng), {});
    inserter.Insert(points, drifted[k], drifted_map);
    auto correction = closer.AddNode(static_cast<int>(k), to_corrected * drifted[k], points);
    if (correction) {
      to_corrected = correction->node_poses.back() * drifted[k].inverse();
      last = std::move(correction);
    }
  }
  if (auto final_correction = closer.Flush()) last = std::move(final_correction);
  ASSERT_TRUE(last.has_value());
  EXPECT_GT(closer.stats().closures, 0);
  const Pose2D end = closer.graph().pose(closer.graph().size() - 1);
  EXPECT_LT((end.translation() - truth.back().translation()).norm(), 0.25);
  EXPECT_LT(std::abs(NormalizeAngle(end.theta - truth.back().theta)), 0.06);
  // Most of the corrected map lies on the world's walls; the drifted one misplaces most of them.
  EXPECT_GT(OnWalls(last->map, world), 0.75);
  EXPECT_LT(OnWalls(drifted_map, world), 0.4);
}

}  // namespace
}  // namespace pslam
