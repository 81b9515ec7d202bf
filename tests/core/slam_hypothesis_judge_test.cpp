// Judging a hypothesis against what was observed of it: not before its observed part holds enough
// structure to score, then by Psi, with a second look a few cells over before a refutation.
#include <gtest/gtest.h>

#include "pslam/slam/hypothesis_judge.hpp"

namespace pslam {
namespace {

constexpr double kResolution = 0.05;
constexpr OccupancyGrid::Cell kFree = -2000;
constexpr OccupancyGrid::Cell kOccupied = 3000;

// A 10 m x 2 m hypothesis (200 x 40 cells) predicting a wall along y = 0.
Hypothesis WallAlongX() {
  Hypothesis h;
  for (int x = 0; x < 200; ++x) {
    for (int y = 0; y < 40; ++y) h.cells.push_back({{x, y}, y == 0});
  }
  return h;
}

// The map after observing the cells with x < 'seen_until', where the true wall is at y = wall_y.
OccupancyGrid Observed(int seen_until, int wall_y) {
  OccupancyGrid map(kResolution);
  for (int x = 0; x < seen_until; ++x) {
    for (int y = 0; y < 40; ++y) map.MutableAt(x, y) = y == wall_y ? kOccupied : kFree;
  }
  return map;
}

Verdict JudgeAfter(int seen_until, int wall_y) {
  const Hypothesis h = WallAlongX();
  return Judge(GatherEvidence(h, Observed(seen_until, wall_y), {}, 1), HypothesisJudgeOptions{});
}

TEST(HypothesisJudgeTest, EvidenceCountsObservedWallsOnBothSides) {
  const ObservedEvidence e = GatherEvidence(WallAlongX(), Observed(120, 20), {}, 1);
  EXPECT_DOUBLE_EQ(e.observed_fraction, 0.6);
  EXPECT_NEAR(e.predicted_walls_m, 120 * kResolution, 1e-9);
  EXPECT_NEAR(e.observed_walls_m, 120 * kResolution, 1e-9);
  EXPECT_DOUBLE_EQ(e.psi, 0.0);  // the wall is 1 m off
}

TEST(HypothesisJudgeTest, RightPredictionIsConfirmedWrongOneRefuted) {
  EXPECT_EQ(JudgeAfter(120, 0), Verdict::kConfirmed);
  EXPECT_EQ(JudgeAfter(120, 20), Verdict::kRefuted);
}

TEST(HypothesisJudgeTest, AMapMovedByAFewCellsDoesNotRefuteARightPrediction) {
  // The predicted wall is there, two cells (10 cm) from where the hypothesis drew it: beyond Psi's
  // one-cell tolerance, within the second look's 15 cm.
  const Hypothesis h = WallAlongX();
  const OccupancyGrid moved = Observed(120, 2);
  const ObservedEvidence e = GatherEvidence(h, moved, {}, 1);
  EXPECT_DOUBLE_EQ(e.psi, 0.0);
  EXPECT_EQ(Judge(e, HypothesisJudgeOptions{}), Verdict::kRefuted);
  EXPECT_DOUBLE_EQ(RegisteredSimilarity(h, moved, {}, 1, 3), 1.0);
  EXPECT_EQ(JudgeOnMap(h, e, moved, {}, 1, HypothesisJudgeOptions{}), Verdict::kConfirmed);
  HypothesisJudgeOptions no_second_look;
  no_second_look.registration_m = 0.0;
  EXPECT_EQ(JudgeOnMap(h, e, moved, {}, 1, no_second_look), Verdict::kRefuted);
  // A wall 1 m off is another structure, not a moved map.
  const OccupancyGrid elsewhere = Observed(120, 20);
  EXPECT_EQ(JudgeOnMap(h, GatherEvidence(h, elsewhere, {}, 1), elsewhere, {}, 1, HypothesisJudgeOptions{}),
            Verdict::kRefuted);
}

TEST(HypothesisJudgeTest, NotJudgedBeforeEnoughIsSeen) {
  EXPECT_EQ(JudgeAfter(0, 20), Verdict::kUndecided);
  EXPECT_EQ(JudgeAfter(60, 20), Verdict::kUndecided);  // 30 % seen
}

TEST(HypothesisJudgeTest, NotJudgedOnTooLittleStructure) {
  // Over half seen, but of a hypothesis whose walls (predicted and observed) are 3.5 m short of
  // the 4 m bar: a metre-scale wall piece a cell or two off would decide it either way.
  Hypothesis h;
  for (int x = 0; x < 70; ++x) {
    for (int y = 0; y < 100; ++y) h.cells.push_back({{x, y}, y == 0});
  }
  OccupancyGrid map(kResolution);
  for (int x = 0; x < 70; ++x) {
    for (int y = 0; y < 60; ++y) map.MutableAt(x, y) = y == 30 ? kOccupied : kFree;
  }
  const ObservedEvidence e = GatherEvidence(h, map, {}, 1);
  EXPECT_GE(e.observed_fraction, 0.5);
  EXPECT_DOUBLE_EQ(e.psi, 0.0);
  EXPECT_EQ(Judge(e, HypothesisJudgeOptions{}), Verdict::kUndecided);
  HypothesisJudgeOptions lax;
  lax.min_structure_m = 3.0;
  EXPECT_EQ(Judge(e, lax), Verdict::kRefuted);
}

TEST(HypothesisJudgeTest, MissingPredictedWallsRefute) {
  // The observation has no wall at all where 6 m of wall was predicted.
  EXPECT_EQ(JudgeAfter(120, -1), Verdict::kRefuted);
}

TEST(HypothesisJudgeTest, UndecidedCellsAreNoEvidence) {
  // The predicted wall is seen as a wall along its first half; along the second half the laser
  // has only grazed it once, and those cells are still uncertain (p = 0.48).
  Hypothesis h;
  for (int x = 0; x < 200; ++x) h.cells.push_back({{x, 0}, true});
  OccupancyGrid map(kResolution);
  for (int x = 0; x < 200; ++x) map.MutableAt(x, 0) = x < 100 ? kOccupied : OccupancyGrid::Cell{-100};
  EXPECT_DOUBLE_EQ(GatherEvidence(h, map, {}, 1).psi, 1.0);
}

TEST(HypothesisJudgeTest, FullySeenIsJudgedWhateverItsStructure) {
  Hypothesis h;
  for (int x = 0; x < 20; ++x) h.cells.push_back({{x, 0}, true});  // 1 m of wall
  OccupancyGrid map(kResolution);
  for (int x = 0; x < 20; ++x) map.MutableAt(x, 0) = kOccupied;
  EXPECT_EQ(Judge(GatherEvidence(h, map, {}, 1), HypothesisJudgeOptions{}), Verdict::kConfirmed);
}

}  // namespace
}  // namespace pslam
