// A hypothesis seen wrong in one place loses its cells around that place, and only there.
#include "pslam/slam/local_refutation.hpp"

#include <gtest/gtest.h>

namespace pslam {
namespace {

constexpr OccupancyGrid::Cell kWall = 2000, kFloor = -2000, kUndecided = 0;

// A hypothesis over the 40 x 20 cells x in [0, 40), y in [0, 20): floor, with a wall along y = 10.
Hypothesis Predicted() {
  Hypothesis h;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 40; ++x) h.cells.push_back({{x, y}, y == 10});
  }
  return h;
}

std::vector<HypothesisCell> CellsAt(const Hypothesis& h, const std::vector<Eigen::Vector2i>& at) {
  std::vector<HypothesisCell> out;
  for (const HypothesisCell& c : h.cells) {
    for (const Eigen::Vector2i& a : at) {
      if (c.cell == a) out.push_back(c);
    }
  }
  return out;
}

TEST(LocalRefutation, AWallWherePredictedFloorWasIsAContradiction) {
  const Hypothesis h = Predicted();
  OccupancyGrid map(0.05);
  map.MutableAt(5, 3) = kWall;      // a block's face in the predicted floor
  map.MutableAt(6, 3) = kUndecided; // seen once: no evidence either way
  map.MutableAt(7, 3) = kFloor;     // as predicted
  map.MutableAt(8, 11) = kWall;     // the predicted wall, one cell off: within tolerance
  map.MutableAt(9, 10) = kWall;     // the predicted wall where it was predicted
  const auto seen = CellsAt(h, {{5, 3}, {6, 3}, {7, 3}, {8, 11}, {9, 10}});
  const auto wrong = FindContradictions(seen, h, map, CellClassifier(), 1);
  ASSERT_EQ(wrong.size(), 1u);
  EXPECT_EQ(wrong[0], Eigen::Vector2i(5, 3));
}

TEST(LocalRefutation, FloorWhereAWallWasPredictedIsAContradictionUnlessAWallIsNear) {
  const Hypothesis h = Predicted();
  OccupancyGrid map(0.05);
  map.MutableAt(20, 10) = kFloor;  // the predicted wall is missing here
  map.MutableAt(30, 10) = kFloor;  // ... but not here: the wall stands a cell further on
  map.MutableAt(30, 11) = kWall;
  const auto seen = CellsAt(h, {{20, 10}, {30, 10}});
  const auto wrong = FindContradictions(seen, h, map, CellClassifier(), 1);
  ASSERT_EQ(wrong.size(), 1u);
  EXPECT_EQ(wrong[0], Eigen::Vector2i(20, 10));
}

TEST(LocalRefutation, CellsNearAContradictionAreTakenAndTheRestStay) {
  Hypothesis h = Predicted();
  h.undecided_cells = {{{6, 6}, false}, {{35, 15}, false}};
  const std::size_t before = h.cells.size();
  const auto taken = TakeNear(h, {{5, 5}}, 3.0);
  for (const HypothesisCell& c : taken) EXPECT_LE((c.cell - Eigen::Vector2i(5, 5)).squaredNorm(), 9);
  for (const HypothesisCell& c : h.cells) EXPECT_GT((c.cell - Eigen::Vector2i(5, 5)).squaredNorm(), 9);
  // 29 lattice points lie within 3 cells of a point; one of the undecided cells is among them.
  EXPECT_EQ(taken.size(), 29u + 1u);
  EXPECT_EQ(h.cells.size(), before - 29u);
  ASSERT_EQ(h.undecided_cells.size(), 1u);
  EXPECT_EQ(h.undecided_cells[0].cell, Eigen::Vector2i(35, 15));
  EXPECT_TRUE(TakeNear(h, {}, 3.0).empty());
  EXPECT_TRUE(TakeNear(h, {{5, 5}}, 0.0).empty());
}

}  // namespace
}  // namespace pslam
