// The predictor takes the reference of an unexplored region from a library map (another map of
// the site) when the map being built has nothing like the target's surroundings.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pslam/predict/library_map.hpp"
#include "pslam/predict/structure_predictor.hpp"

namespace pslam {
namespace {

constexpr double kResolution = 0.05;
constexpr OccupancyGrid::Cell kWall = 3500;   // p = 0.97
constexpr OccupancyGrid::Cell kFree = -2000;  // p = 0.12

void PaintFree(OccupancyGrid& grid, double x0, double y0, double x1, double y1) {
  const Eigen::Vector2i a = grid.WorldToCell({x0, y0}), b = grid.WorldToCell({x1, y1});
  for (int y = a.y(); y <= b.y(); ++y) {
    for (int x = a.x(); x <= b.x(); ++x) grid.MutableAt(x, y) = kFree;
  }
}

void PaintWall(OccupancyGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const int steps = static_cast<int>(std::ceil((b - a).norm() / (0.25 * kResolution)));
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2i c = grid.WorldToCell(a + (b - a) * (static_cast<double>(i) / steps));
    grid.MutableAt(c.x(), c.y()) = kWall;
  }
}

// One floor: a 12 m corridor (y in [0, 2]) and a 7 m x 6 m room north of it at x in [3, 10], with
// a door, a wall stub and a pillar, so that the room has corners inside.
OccupancyGrid Floor() {
  OccupancyGrid grid(kResolution);
  PaintFree(grid, 0.0, 0.0, 12.0, 2.0);
  PaintFree(grid, 3.01, 2.0, 10.01, 8.0);
  PaintWall(grid, {0.0, 0.01}, {12.0, 0.01});
  PaintWall(grid, {0.01, 0.0}, {0.01, 2.0});
  PaintWall(grid, {12.0, 0.0}, {12.0, 2.0});
  PaintWall(grid, {0.0, 2.01}, {5.01, 2.01});
  PaintWall(grid, {6.01, 2.01}, {12.0, 2.01});  // a 1 m door at x in [5, 6]
  PaintWall(grid, {3.01, 8.0}, {10.01, 8.0});
  PaintWall(grid, {3.01, 2.0}, {3.01, 8.0});
  PaintWall(grid, {10.01, 2.0}, {10.01, 8.0});
  PaintWall(grid, {5.51, 6.0}, {5.51, 8.0});  // stub
  for (const double y : {4.0, 4.6}) PaintWall(grid, {8.01, y}, {9.01, y});
  for (const double x : {8.01, 9.01}) PaintWall(grid, {x, 4.0}, {x, 4.6});  // pillar
  return grid;
}

// 'grid' turned by 90 degrees and moved 40 m away: another map's frame. Exact on the lattice.
OccupancyGrid TurnedAndMoved(const OccupancyGrid& grid) {
  OccupancyGrid out(kResolution);
  const CellBox box = grid.KnownBounds();
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      if (grid.IsKnown(x, y)) out.MutableAt(800 - y, 300 + x) = grid.At(x, y);
    }
  }
  return out;
}

// The floor being built: its room explored only up to x = 6.5 m through the door.
OccupancyGrid HalfExplored(const OccupancyGrid& truth) {
  OccupancyGrid built = truth;
  const Eigen::Vector2i a = built.WorldToCell({6.5, 2.06}), b = built.WorldToCell({10.5, 8.5});
  for (int y = a.y(); y <= b.y(); ++y) {
    for (int x = a.x(); x <= b.x(); ++x) built.MutableAt(x, y) = OccupancyGrid::kUnknown;
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

TEST(LibraryPrediction, WithoutALibraryARoomWithNoLookAlikeIsNotPredicted) {
  const OccupancyGrid truth = Floor();
  const OccupancyGrid built = HalfExplored(truth);
  const Eigen::Vector2i target = built.WorldToCell({6.47, 5.0});
  StructurePredictor predictor;
  EXPECT_FALSE(predictor.Predict(built, target, 1.0).has_value());
  EXPECT_NE(predictor.last_report().outcome, PredictionReport::Outcome::kHypothesis);
}

TEST(LibraryPrediction, TheReferenceComesFromALibraryMapAndPredictsTheHiddenCells) {
  const OccupancyGrid truth = Floor();
  const OccupancyGrid built = HalfExplored(truth);
  const Eigen::Vector2i target = built.WorldToCell({6.47, 5.0});
  ASSERT_TRUE(built.IsKnown(target.x(), target.y()));
  ASSERT_FALSE(built.IsKnown(target.x() + 1, target.y()));
  const PredictorOptions options;
  StructurePredictor predictor(options, {MakeLibraryMap("site-a/3", TurnedAndMoved(truth), options)});
  const auto h = predictor.Predict(built, target, 1.0);
  const PredictionReport& report = predictor.last_report();
  ASSERT_TRUE(h.has_value()) << "outcome " << static_cast<int>(report.outcome) << " best psi " << report.best_psi;
  EXPECT_EQ(h->reference_map, "site-a/3");
  EXPECT_GE(h->psi, options.similarity_threshold);
  // Gamma undoes the library map's turn: -90 degrees.
  EXPECT_NEAR(NormalizeAngle(h->theta + std::numbers::pi / 2), 0.0, 2.0 * std::numbers::pi / 180.0);

  // Cell by cell against the truth: predicted free cells are free, predicted walls lie on walls
  // (within a cell), and the hidden walls are found.
  ASSERT_GT(h->cells.size(), 2000u);
  int walls = 0, walls_right = 0, free = 0, free_right = 0;
  for (const HypothesisCell& c : h->cells) {
    ASSERT_FALSE(built.IsKnown(c.cell.x(), c.cell.y()));
    if (c.occupied) {
      ++walls;
      walls_right += OccupiedNear(truth, c.cell, 1);
    } else if (truth.IsKnown(c.cell.x(), c.cell.y())) {
      ++free;
      free_right += truth.At(c.cell.x(), c.cell.y()) < 0 || OccupiedNear(truth, c.cell, 1);
    }
  }
  ASSERT_GT(walls, 100);
  EXPECT_GT(static_cast<double>(walls_right) / walls, 0.9);
  ASSERT_GT(free, 1000);
  EXPECT_GT(static_cast<double>(free_right) / free, 0.97);
  OccupancyGrid predicted(kResolution);
  for (const HypothesisCell& c : h->cells) predicted.MutableAt(c.cell.x(), c.cell.y()) = c.occupied ? kWall : kFree;
  int hidden_walls = 0, found = 0;
  const Eigen::Vector2i a = built.WorldToCell({6.5, 2.06}), b = built.WorldToCell({10.5, 8.5});
  for (int y = a.y(); y <= b.y(); ++y) {
    for (int x = a.x(); x <= b.x(); ++x) {
      if (truth.At(x, y) <= 620) continue;
      ++hidden_walls;
      found += OccupiedNear(predicted, {x, y}, 1);
    }
  }
  ASSERT_GT(hidden_walls, 100);
  EXPECT_GT(static_cast<double>(found) / hidden_walls, 0.9);
}

TEST(LibraryPrediction, ALibraryMapOfAnotherResolutionIsSkipped) {
  const OccupancyGrid truth = Floor();
  const OccupancyGrid built = HalfExplored(truth);
  OccupancyGrid coarse(0.1);
  coarse.MutableAt(0, 0) = kWall;
  const PredictorOptions options;
  StructurePredictor predictor(options, {MakeLibraryMap("coarse", coarse, options)});
  EXPECT_FALSE(predictor.Predict(built, built.WorldToCell({6.47, 5.0}), 1.0).has_value());
}

TEST(LibraryPrediction, ALibraryMapNeedsAnId) {
  EXPECT_THROW(MakeLibraryMap("", OccupancyGrid(kResolution), PredictorOptions{}), std::invalid_argument);
}

// A loop closure moves the map being built, not the library map: Gamma is followed by the move.
TEST(LibraryPrediction, MovingTheMapLeavesALibraryReferenceWhereItIs) {
  Hypothesis h;
  h.reference_map = "site-a/3";
  h.theta = 0.3;
  h.target_control_point = {2.0, 1.0};
  h.reference_control_point = {40.0, -5.0};
  h.translation = h.target_control_point - h.reference_control_point;
  h.reference_cell = {800, -100};
  const Pose2D before = ReferenceToTarget(h);
  const Pose2D move(0.4, -0.2, 0.05);
  MoveHypothesis(h, move, kResolution);
  EXPECT_EQ(h.reference_cell, Eigen::Vector2i(800, -100));
  EXPECT_NEAR((h.reference_control_point - Eigen::Vector2d(40.0, -5.0)).norm(), 0.0, 1e-12);
  const Pose2D expected = move * before, after = ReferenceToTarget(h);
  EXPECT_NEAR(after.x, expected.x, 1e-9);
  EXPECT_NEAR(after.y, expected.y, 1e-9);
  EXPECT_NEAR(NormalizeAngle(after.theta - expected.theta), 0.0, 1e-9);
}

}  // namespace
}  // namespace pslam
