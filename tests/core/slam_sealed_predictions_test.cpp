// A predicted room without a way in from the floor the robot has seen is taken out of its hypothesis.
#include "pslam/slam/sealed_predictions.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace pslam {
namespace {

constexpr OccupancyGrid::Cell kWall = 2000, kFloor = -2000;

// A corridor the robot has mapped, x in [0, 40), y in [0, 6), with its north wall at y = 6 seen
// whole, except where it opens, x in [30, 34), onto what the map has not seen.
OccupancyGrid Corridor() {
  OccupancyGrid map(0.05);
  for (int x = 0; x < 40; ++x) {
    for (int y = 0; y < 6; ++y) map.MutableAt(x, y) = kFloor;
    if (x < 30 || x >= 34) map.MutableAt(x, 6) = kWall;
  }
  return map;
}

// Two rooms predicted north of the corridor, y in [7, 17): one over x in [2, 12), whose door
// (x in [5, 8) at y = 6) fell on the corridor's observed wall and so was never predicted; one over
// x in [28, 38), entered through the opening. Each with its own walls at y = 17 and at its sides.
Hypothesis TwoRooms() {
  Hypothesis h;
  for (const int x0 : {2, 28}) {
    for (int x = x0 - 1; x <= x0 + 10; ++x) {
      for (int y = 7; y <= 17; ++y) {
        const bool wall = y == 17 || x == x0 - 1 || x == x0 + 10;
        h.cells.push_back({{x, y}, wall});
      }
    }
  }
  for (int x = 30; x < 34; ++x) h.cells.push_back({{x, 6}, false});  // the opening, predicted floor
  return h;
}

bool Has(const std::vector<HypothesisCell>& cells, const Eigen::Vector2i& at) {
  return std::any_of(cells.begin(), cells.end(), [&](const HypothesisCell& c) { return c.cell == at; });
}

TEST(SealedPredictions, ARoomWithItsDoorOnAnObservedWallIsTakenAndTheOtherStays) {
  Hypothesis h = TwoRooms();
  const std::size_t before = h.cells.size();
  const std::vector<HypothesisCell> taken = TakeSealedOff(h, Corridor(), CellClassifier());
  EXPECT_TRUE(Has(taken, {6, 12})) << "the sealed room's floor";
  EXPECT_TRUE(Has(taken, {6, 17})) << "its far wall, which bounds nothing the robot can reach";
  EXPECT_FALSE(Has(h.cells, {6, 12}));
  EXPECT_TRUE(Has(h.cells, {32, 12})) << "the room entered through the opening";
  EXPECT_TRUE(Has(h.cells, {32, 17})) << "and its walls";
  EXPECT_TRUE(Has(h.cells, {31, 6}));
  EXPECT_EQ(h.cells.size() + taken.size(), before);
}

TEST(SealedPredictions, WallsPredictedAcrossTheOpeningSealTheRoomBehindThem) {
  Hypothesis h = TwoRooms();
  for (HypothesisCell& c : h.cells) {
    if (c.cell.y() == 6) c.occupied = true;
  }
  const std::vector<HypothesisCell> taken = TakeSealedOff(h, Corridor(), CellClassifier());
  EXPECT_TRUE(Has(taken, {32, 12}));
  EXPECT_TRUE(Has(h.cells, {31, 6})) << "the predicted wall itself faces the corridor";
}

TEST(SealedPredictions, UndecidedCellsJoinLikeFloorAndArePredictedToo) {
  OccupancyGrid map = Corridor();
  for (int x = 5; x < 8; ++x) map.MutableAt(x, 6) = 0;  // the door seen once: undecided
  Hypothesis h = TwoRooms();
  for (int x = 5; x < 8; ++x) h.undecided_cells.push_back({{x, 6}, false});
  const std::vector<HypothesisCell> taken = TakeSealedOff(h, map, CellClassifier());
  EXPECT_TRUE(Has(h.cells, {6, 12})) << "reached through the undecided door";
  EXPECT_FALSE(Has(taken, {6, 12}));
  h.undecided_cells = {{{5, 6}, true}, {{6, 6}, true}, {{7, 6}, true}};  // predicted shut instead
  EXPECT_TRUE(Has(TakeSealedOff(h, map, CellClassifier()), {6, 12}));
}

TEST(SealedPredictions, NothingIsTakenFromAnEmptyHypothesis) {
  Hypothesis h;
  EXPECT_TRUE(TakeSealedOff(h, Corridor(), CellClassifier()).empty());
}

}  // namespace
}  // namespace pslam
