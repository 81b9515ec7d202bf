#include "pslam/predict/structure_predictor.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <thread>
#include <vector>

#include "pslam/grid/scan_inserter.hpp"
#include "pslam/predict/async_predictor.hpp"
#include "pslam/sensor/scan_points.hpp"
#include "testing/synthetic_world.hpp"

namespace pslam {
namespace {

constexpr double kResolution = 0.05;
constexpr OccupancyGrid::Cell kWall = 3500;   // p = 0.97, the inserter's clamp
constexpr OccupancyGrid::Cell kFree = -2000;  // p = 0.12

// Synthetic maps are painted directly in log-odds: a free rectangle, then walls on top.
void PaintFree(OccupancyGrid& grid, double x0, double y0, double x1, double y1) {
  const Eigen::Vector2i a = grid.WorldToCell({x0, y0}), b = grid.WorldToCell({x1, y1});
  for (int y = a.y(); y <= b.y(); ++y) {
    for (int x = a.x(); x <= b.x(); ++x) grid.MutableAt(x, y) = kFree;
  }
}

void PaintWall(OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double length = (b - a).norm();
  const int steps = static_cast<int>(std::ceil(length / (0.25 * kResolution)));
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2i c = grid.WorldToCell(a + (b - a) * (static_cast<double>(i) / steps));
    grid.MutableAt(c.x(), c.y()) = kWall;
  }
}

void PaintBox(OccupancyGrid& grid, double x0, double y0, double x1, double y1) {
  PaintWall(grid, {x0, y0}, {x1, y0});
  PaintWall(grid, {x1, y0}, {x1, y1});
  PaintWall(grid, {x1, y1}, {x0, y1});
  PaintWall(grid, {x0, y1}, {x0, y0});
}

// A 7 m x 6 m room north of a corridor, its south-west corner at (x, 2): a door in the south
// wall, a wall stub hanging from the north wall and a pillar, so that it has corners inside.
void PaintRoom(OccupancyGrid& grid, double x) {
  PaintFree(grid, x, 2.0, x + 7.0, 8.0);
  PaintWall(grid, {x, 8.0}, {x + 7.0, 8.0});
  PaintWall(grid, {x, 2.0}, {x, 8.0});
  PaintWall(grid, {x + 7.0, 2.0}, {x + 7.0, 8.0});
  PaintWall(grid, {x + 2.5, 6.0}, {x + 2.5, 8.0});  // stub
  PaintBox(grid, x + 5.0, 4.0, x + 6.0, 4.6);       // pillar
}

// Two identical rooms (x in [2, 9] and [13, 20]) along a 24 m corridor (y in [0, 2]). Walls
// are offset from the 5 cm lattice by a few millimetres, as real walls are.
OccupancyGrid RepeatedRooms() {
  OccupancyGrid grid(kResolution);
  PaintFree(grid, 0.0, 0.0, 24.0, 2.0);
  PaintRoom(grid, 2.01);
  PaintRoom(grid, 13.01);
  PaintWall(grid, {0.0, 0.01}, {24.0, 0.01});
  PaintWall(grid, {0.01, 0.0}, {0.01, 2.0});
  PaintWall(grid, {24.0, 0.0}, {24.0, 2.0});
  // The corridor's north wall, with a 1 m door into each room.
  PaintWall(grid, {0.0, 2.01}, {4.01, 2.01});
  PaintWall(grid, {5.01, 2.01}, {15.01, 2.01});
  PaintWall(grid, {16.01, 2.01}, {24.0, 2.01});
  return grid;
}

// 'truth' with every cell of the box [x0, x1] x [y0, y1] (metres) never observed.
OccupancyGrid Hide(const OccupancyGrid& truth, double x0, double y0, double x1, double y1) {
  OccupancyGrid built = truth;
  const Eigen::Vector2i a = built.WorldToCell({x0, y0}), b = built.WorldToCell({x1, y1});
  for (int y = a.y(); y <= b.y(); ++y) {
    for (int x = a.x(); x <= b.x(); ++x) {
      if (built.IsKnown(x, y)) built.MutableAt(x, y) = OccupancyGrid::kUnknown;
    }
  }
  return built;
}

bool OccupiedNear(const OccupancyGrid& grid, const Eigen::Vector2i& c, int radius) {
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      if (grid.At(c.x() + dx, c.y() + dy) > 620) return true;  // p > 0.65
    }
  }
  return false;
}

struct Scene {
  OccupancyGrid truth;
  OccupancyGrid built;
  Eigen::Vector2i target;
};

// Room A fully explored; room B explored up to x = 16.5 m through its door (its south wall is
// seen from the corridor); the target is a frontier cell at the edge of what was seen.
Scene HalfExploredRooms() {
  Scene s{RepeatedRooms(), OccupancyGrid(kResolution), {}};
  s.built = Hide(s.truth, 16.5, 2.06, 20.5, 8.5);
  s.target = s.built.WorldToCell({16.47, 5.0});
  return s;
}

TEST(StructurePredictor, PredictsTheHiddenHalfOfARepeatedRoom) {
  const Scene scene = HalfExploredRooms();
  ASSERT_TRUE(scene.built.IsKnown(scene.target.x(), scene.target.y()));
  ASSERT_FALSE(scene.built.IsKnown(scene.target.x() + 1, scene.target.y()));
  StructurePredictor predictor;
  const auto h = predictor.Predict(scene.built, scene.target, 12.5);
  const PredictionReport& report = predictor.last_report();
  ASSERT_TRUE(h.has_value()) << "outcome " << static_cast<int>(report.outcome) << " best psi " << report.best_psi;
  EXPECT_GE(h->psi, 0.7);
  EXPECT_EQ(h->id, 1);
  EXPECT_DOUBLE_EQ(h->time, 12.5);
  EXPECT_EQ(h->target_cell, scene.target);
  EXPECT_EQ(h->status, Hypothesis::Status::kPending);
  EXPECT_TRUE(std::isnan(h->psi_observed));
  EXPECT_TRUE(std::isnan(h->hit_ratio));
  // The reference is room A: 11 m to the west, same orientation.
  const Pose2D gamma = ReferenceToTarget(*h);
  EXPECT_NEAR(NormalizeAngle(gamma.theta), 0.0, 2.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(gamma.x, 11.0, 0.15);
  EXPECT_NEAR(gamma.y, 0.0, 0.15);
  EXPECT_NEAR((h->reference_cell - (scene.target - Eigen::Vector2i(220, 0))).cast<double>().norm(), 0.0, 3.0);

  // Never over explored cells; the area is what the cells cover.
  for (const HypothesisCell& c : h->cells) ASSERT_FALSE(scene.built.IsKnown(c.cell.x(), c.cell.y()));
  EXPECT_NEAR(h->area_m2, static_cast<double>(h->cells.size()) * kResolution * kResolution, 1e-9);

  // Predicted walls are the hidden walls: precision and recall within one cell.
  int predicted_walls = 0, correct = 0;
  for (const HypothesisCell& c : h->cells) {
    if (!c.occupied) continue;
    ++predicted_walls;
    correct += OccupiedNear(scene.truth, c.cell, 1);
  }
  ASSERT_GT(predicted_walls, 100);
  EXPECT_GT(static_cast<double>(correct) / predicted_walls, 0.9);
  OccupancyGrid predicted(kResolution);
  for (const HypothesisCell& c : h->cells) predicted.MutableAt(c.cell.x(), c.cell.y()) = c.occupied ? kWall : kFree;
  int hidden_walls = 0, found = 0;
  const CellBox box{scene.target - Eigen::Vector2i(100, 100), scene.target + Eigen::Vector2i(99, 99)};
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      if (scene.built.IsKnown(x, y) || scene.truth.At(x, y) <= 620) continue;
      ++hidden_walls;
      found += OccupiedNear(predicted, {x, y}, 1);
    }
  }
  ASSERT_GT(hidden_walls, 100);
  EXPECT_GT(static_cast<double>(found) / hidden_walls, 0.9);

  // Once the robot has seen the rest of room B, the hypothesis is confirmed by the real map.
  EXPECT_GT(ObservedSimilarity(*h, scene.truth), 0.8);
  EXPECT_EQ(predictor.stats().hypotheses, 1u);
  EXPECT_GT(predictor.stats().last_ms, 0.0);
}

// Rooms A and B as before, and a room C east of them that looks like both from its door to 3.5 m
// in (where room B is explored) but is only 5 m wide, with no pillar. A and C fit B's explored
// half equally well and predict its hidden half differently: the match is ambiguous.
TEST(StructurePredictor, TwoEquallyGoodReferencesThatDisagreeGiveNoHypothesis) {
  Scene scene = HalfExploredRooms();
  for (OccupancyGrid* grid : {&scene.truth, &scene.built}) {
    PaintFree(*grid, 24.0, 0.0, 35.0, 2.0);
    PaintWall(*grid, {24.0, 0.01}, {35.0, 0.01});
    PaintFree(*grid, 24.01, 2.0, 29.01, 8.0);
    PaintWall(*grid, {24.01, 8.0}, {29.01, 8.0});
    PaintWall(*grid, {24.01, 2.0}, {24.01, 8.0});
    PaintWall(*grid, {29.01, 2.0}, {29.01, 8.0});
    PaintWall(*grid, {26.51, 6.0}, {26.51, 8.0});  // the stub, as in A and B
    PaintWall(*grid, {24.0, 2.01}, {26.01, 2.01});
    PaintWall(*grid, {27.01, 2.01}, {35.0, 2.01});  // its door at the same place as theirs
  }
  StructurePredictor predictor;
  EXPECT_FALSE(predictor.Predict(scene.built, scene.target, 1.0).has_value());
  EXPECT_EQ(predictor.last_report().outcome, PredictionReport::Outcome::kAmbiguous)
      << "outcome " << static_cast<int>(predictor.last_report().outcome);
  EXPECT_EQ(predictor.stats().ambiguous, 1u);

  // The paper's rule, the best match whatever the others say, predicts.
  PredictorOptions paper;
  paper.ambiguity_margin = 0.0;
  StructurePredictor best_only(paper);
  EXPECT_TRUE(best_only.Predict(scene.built, scene.target, 1.0).has_value());
}

// The same two rooms, turned by 'degrees' about the origin, mapped by the real inverse sensor
// model from 360-degree scans: walls come out as laser maps draw them, with jagged oblique edges
// and undecided cells at the fringes, instead of clean painted lines.
OccupancyGrid ScannedRooms(double degrees) {
  const Eigen::Rotation2Dd turn(degrees * std::numbers::pi / 180.0);
  std::vector<testing::Segment> walls;
  auto wall = [&](double x0, double y0, double x1, double y1) {
    walls.push_back({turn * Eigen::Vector2d(x0, y0), turn * Eigen::Vector2d(x1, y1)});
  };
  for (const double x : {2.0, 13.0}) {
    wall(x, 8, x + 7, 8);
    wall(x, 2, x, 8);
    wall(x + 7, 2, x + 7, 8);
    wall(x + 2.5, 6, x + 2.5, 8);
    wall(x + 5, 4, x + 6, 4);
    wall(x + 6, 4, x + 6, 4.6);
    wall(x + 6, 4.6, x + 5, 4.6);
    wall(x + 5, 4.6, x + 5, 4);
  }
  wall(0, 0, 24, 0);
  wall(0, 0, 0, 2);
  wall(24, 0, 24, 2);
  wall(0, 2, 4, 2);
  wall(5, 2, 15, 2);
  wall(16, 2, 24, 2);
  std::vector<Eigen::Vector2d> stops;
  for (double x = 0.5; x < 24.0; x += 1.0) stops.emplace_back(x, 1.0);
  for (const double room : {2.0, 13.0}) {
    for (const double x : {1.0, 3.5, 6.0}) {
      for (const double y : {3.0, 4.5, 5.5, 7.5}) stops.emplace_back(room + x, y);
    }
  }
  OccupancyGrid grid(kResolution);
  const ScanInserter inserter;
  for (const Eigen::Vector2d& stop : stops) {
    const Eigen::Vector2d p = turn * stop;
    const Pose2D pose(p.x(), p.y(), 0.0);
    LaserScan scan;
    scan.angle_min = -std::numbers::pi;
    scan.angle_increment = std::numbers::pi / 360.0;
    scan.max_range = 20.0;
    for (int i = 0; i < 720; ++i) {
      const double a = scan.BeamAngle(static_cast<std::size_t>(i));
      scan.ranges.push_back(static_cast<float>(std::min(20.0, testing::RayHit(p, {std::cos(a), std::sin(a)}, walls))));
    }
    inserter.Insert(ToScanPoints(scan, ScanPointsOptions{}), pose, grid);
  }
  return grid;
}

TEST(StructurePredictor, PredictsARoomMappedByScansAtAnObliqueAngle) {
  constexpr double kDegrees = 30.0;
  const Eigen::Rotation2Dd turn(kDegrees * std::numbers::pi / 180.0);
  const OccupancyGrid truth = ScannedRooms(kDegrees);
  // Hide what lies east of x = 16.5 m in room B (in the building's own frame).
  OccupancyGrid built = truth;
  const CellBox known = truth.KnownBounds();
  for (int y = known.min.y(); y <= known.max.y(); ++y) {
    for (int x = known.min.x(); x <= known.max.x(); ++x) {
      const Eigen::Vector2d p = turn.inverse() * truth.CellCenter({x, y});
      if (p.x() > 16.5 && p.x() < 20.6 && p.y() > 2.1 && p.y() < 8.6 && built.IsKnown(x, y)) {
        built.MutableAt(x, y) = OccupancyGrid::kUnknown;
      }
    }
  }
  const Eigen::Vector2i target = built.WorldToCell(turn * Eigen::Vector2d(16.45, 5.0));
  StructurePredictor predictor;
  const auto h = predictor.Predict(built, target, 0.0);
  ASSERT_TRUE(h.has_value()) << "best psi " << predictor.last_report().best_psi;
  EXPECT_GE(h->psi, 0.7);
  const Pose2D gamma = ReferenceToTarget(*h);  // room A carried onto room B: 11 m along the building
  const Eigen::Vector2d shift = turn * Eigen::Vector2d(11.0, 0.0);
  EXPECT_NEAR(NormalizeAngle(gamma.theta), 0.0, 2.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(gamma.x, shift.x(), 0.2);
  EXPECT_NEAR(gamma.y, shift.y(), 0.2);
  for (const HypothesisCell& c : h->cells) ASSERT_FALSE(built.IsKnown(c.cell.x(), c.cell.y()));
  EXPECT_GT(ObservedSimilarity(*h, truth), 0.7);
}

// Walls at irregular angles and lengths: corners exist, but no two neighbourhoods look alike.
OccupancyGrid IrregularWorld(unsigned seed) {
  OccupancyGrid grid(kResolution);
  PaintFree(grid, 0.0, 0.0, 30.0, 30.0);
  std::mt19937 rng(seed);  // raw engine output is portable, unlike std:: distributions
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng()) / 4294967296.0); };
  for (int i = 0; i < 18; ++i) {
    // A random polygon of 3 to 5 vertices around a random centre.
    const Eigen::Vector2d centre(uniform(3.0, 27.0), uniform(3.0, 27.0));
    const int n = 3 + static_cast<int>(rng() % 3);
    std::vector<Eigen::Vector2d> vertices;
    double angle = uniform(0.0, 2.0 * std::numbers::pi);
    for (int k = 0; k < n; ++k) {
      angle += uniform(0.6, 2.0 * std::numbers::pi / n);
      const double radius = uniform(0.8, 2.5);
      vertices.emplace_back(centre + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
    for (int k = 0; k < n; ++k) PaintWall(grid, vertices[k], vertices[(k + 1) % n]);
  }
  return grid;
}

TEST(StructurePredictor, IrregularWorldYieldsNoHypothesis) {
  const OccupancyGrid truth = IrregularWorld(7);
  const OccupancyGrid built = Hide(truth, 15.0, 10.0, 22.0, 20.0);
  const Eigen::Vector2i target = built.WorldToCell({14.97, 15.0});
  StructurePredictor predictor;
  const auto h = predictor.Predict(built, target, 0.0);
  const PredictionReport& report = predictor.last_report();
  EXPECT_FALSE(h.has_value()) << "psi " << h->psi;
  // The search did run: there is a control point and corners to pair with.
  EXPECT_EQ(report.outcome, PredictionReport::Outcome::kBelowThreshold);
  EXPECT_GT(report.reference_corners, 10);
  EXPECT_LT(report.best_psi, 0.7);
  EXPECT_EQ(predictor.stats().below_threshold, 1u);
}

TEST(StructurePredictor, NoIrregularWorldOfTenYieldsAHypothesis) {
  StructurePredictor predictor;
  int searched = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const OccupancyGrid built = Hide(IrregularWorld(seed), 15.0, 10.0, 22.0, 20.0);
    EXPECT_FALSE(predictor.Predict(built, built.WorldToCell({14.97, 15.0}), 0.0).has_value()) << "seed " << seed;
    searched += predictor.last_report().outcome == PredictionReport::Outcome::kBelowThreshold;
  }
  EXPECT_GE(searched, 5);  // most worlds had a control point and enough structure to compare
}

TEST(StructurePredictor, NoCornerNearTheTargetNoPrediction) {
  OccupancyGrid grid(kResolution);
  PaintFree(grid, 0.0, 0.0, 20.0, 20.0);
  PaintBox(grid, 1.0, 1.0, 4.0, 4.0);
  StructurePredictor predictor;
  EXPECT_FALSE(predictor.Predict(grid, grid.WorldToCell({15.0, 15.0}), 0.0).has_value());
  EXPECT_EQ(predictor.last_report().outcome, PredictionReport::Outcome::kNoControlPoint);
  EXPECT_FALSE(predictor.Predict(OccupancyGrid(kResolution), {0, 0}, 0.0).has_value());  // empty map
}

TEST(StructurePredictor, TakeExploredDropsNewlyObservedCells) {
  const Scene scene = HalfExploredRooms();
  StructurePredictor predictor;
  auto h = predictor.Predict(scene.built, scene.target, 0.0);
  ASSERT_TRUE(h.has_value());
  const std::size_t before = h->cells.size();
  const double area = h->area_m2;
  EXPECT_TRUE(TakeExplored(*h, scene.built).empty());  // nothing new seen yet
  EXPECT_TRUE(std::isnan(ObservedSimilarity(*h, scene.built)));

  // The robot steps in and sees the strip x in [16.5, 18.5] m.
  const OccupancyGrid later = Hide(scene.truth, 18.5, 2.06, 20.5, 8.5);
  std::size_t newly_known = 0;
  for (const HypothesisCell& c : h->cells) newly_known += later.IsKnown(c.cell.x(), c.cell.y());
  ASSERT_GT(newly_known, 0u);
  ASSERT_LT(newly_known, before);
  EXPECT_GT(ObservedSimilarity(*h, later), 0.8);  // the observed strip agrees with the prediction
  const std::vector<HypothesisCell> taken = TakeExplored(*h, later);
  EXPECT_EQ(taken.size(), newly_known);
  for (const HypothesisCell& c : taken) EXPECT_TRUE(later.IsKnown(c.cell.x(), c.cell.y()));
  EXPECT_EQ(h->cells.size(), before - newly_known);
  for (const HypothesisCell& c : h->cells) EXPECT_FALSE(later.IsKnown(c.cell.x(), c.cell.y()));
  EXPECT_DOUBLE_EQ(h->area_m2, area);  // the area predicted when it was made
}

TEST(StructurePredictor, UndecidedCellsArePredictedApartFromNeverObservedOnes) {
  Scene scene = HalfExploredRooms();
  // The first metre of the hidden half was seen once, too little to decide (p = 0.5).
  const Eigen::Vector2i a = scene.built.WorldToCell({16.5, 2.06}), b = scene.built.WorldToCell({17.5, 8.5});
  int undecided = 0;
  for (int y = a.y(); y <= b.y(); ++y) {
    for (int x = a.x(); x <= b.x(); ++x) {
      if (scene.built.IsKnown(x, y) || !scene.truth.IsKnown(x, y)) continue;
      scene.built.MutableAt(x, y) = 0;
      ++undecided;
    }
  }
  ASSERT_GT(undecided, 100);
  StructurePredictor predictor;
  auto h = predictor.Predict(scene.built, scene.target, 0.0);
  ASSERT_TRUE(h.has_value()) << "outcome " << static_cast<int>(predictor.last_report().outcome);
  for (const HypothesisCell& c : h->cells) ASSERT_FALSE(scene.built.IsKnown(c.cell.x(), c.cell.y()));
  ASSERT_GT(h->undecided_cells.size(), 0.8 * undecided);
  int right = 0;
  for (const HypothesisCell& c : h->undecided_cells) {
    ASSERT_EQ(scene.built.At(c.cell.x(), c.cell.y()), 0);
    right += c.occupied == OccupiedNear(scene.truth, c.cell, 1);
  }
  EXPECT_GT(right, 0.9 * static_cast<double>(h->undecided_cells.size()));
  // They count apart from the predicted area, which is the never-observed part.
  EXPECT_NEAR(h->area_m2, static_cast<double>(h->cells.size()) * kResolution * kResolution, 1e-9);

  // Still undecided: nothing to take. Decided by the real map: all taken.
  const CellClassifier classify;
  EXPECT_TRUE(TakeDecided(*h, scene.built, classify).empty());
  const std::size_t count = h->undecided_cells.size();
  EXPECT_EQ(TakeDecided(*h, scene.truth, classify).size(), count);
  EXPECT_TRUE(h->undecided_cells.empty());
}

TEST(StructurePredictor, ObservedSimilarityIsLowForAWrongPrediction) {
  Hypothesis h;
  for (int x = 0; x < 40; ++x) {
    h.cells.push_back({{x, 10}, true});  // a predicted wall ...
    for (int y = 0; y < 10; ++y) h.cells.push_back({{x, y}, false});
  }
  OccupancyGrid later(kResolution);
  for (int x = 0; x < 40; ++x) {
    for (int y = 0; y <= 10; ++y) later.MutableAt(x, y) = y == 3 ? kWall : kFree;  // ... is elsewhere
  }
  EXPECT_DOUBLE_EQ(ObservedSimilarity(h, later), 0.0);
  later.MutableAt(5, 10) = kWall;
  EXPECT_GT(ObservedSimilarity(h, later), 0.0);
  EXPECT_LT(ObservedSimilarity(h, later), 0.1);
}

TEST(AsyncPredictor, PredictsRoomsInTheBackground) {
  const Scene scene = HalfExploredRooms();
  AsyncPredictor async;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(async.Request(scene.built, scene.target, 3.0));
  std::optional<Hypothesis> h;
  while (!h && std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) {
    h = async.TakeResult();
    if (!h) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(h.has_value());
  EXPECT_GE(h->psi, 0.7);
  EXPECT_DOUBLE_EQ(h->time, 3.0);
  const AsyncPredictorStats stats = async.stats();
  EXPECT_EQ(stats.completed, 1u);
  EXPECT_EQ(stats.hypotheses, 1u);
  EXPECT_GT(stats.last_ms, 0.0);
  EXPECT_EQ(stats.last_report.outcome, PredictionReport::Outcome::kHypothesis);
  EXPECT_FALSE(async.TakeResult().has_value());  // taken once
}

}  // namespace
}  // namespace pslam
