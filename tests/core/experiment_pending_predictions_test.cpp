// A skip-predicted run does not end on predictions nothing has checked. Wrong predictions built on
// one another can cover every frontier within minutes: in generated office 22, run seed 2, the
// skip run ends at 450 s as explored, with 49 % of the reachable floor mapped or predicted; full
// coverage maps 98.9 %.
#include <gtest/gtest.h>

#include "pslam/experiment/equal_coverage.hpp"
#include "testing/skip_run.hpp"

namespace pslam {
namespace {

ExplorationOptions WithPendingRule(const FloorPlan& plan, bool verify_pending) {
  ExplorationOptions options = testing::SkipRunOptions(plan, 2, 1000.0);
  options.verify_pending_predictions = verify_pending;
  return options;
}

TEST(PendingPredictionsTest, ASkipRunDoesNotEndWhilePendingPredictionsCoverItsFrontiers) {
  const FloorPlan plan = GenerateFloorPlan(FloorPlanFamily::kOffice, 22);
  const OccupancyGrid reachable = ReachableFreeCells(plan.world, plan.start.translation());

  ExplorationRun trusting(plan.world, plan.start, WithPendingRule(plan, false));
  trusting.Run();
  ASSERT_EQ(trusting.state(), ExplorationState::kExplored) << "the case no longer arises: " << trusting.time() << " s";
  const double trusted = MappedOrPredictedNow(trusting, reachable);
  EXPECT_LT(trusted, 0.5);

  ExplorationRun checking(plan.world, plan.start, WithPendingRule(plan, true));
  checking.Run();
  // It goes on past where the other ended. Checking the predictions adds little at first (what
  // it looks at was predicted already), then what they got wrong shows, and the floor accounted
  // for grows again: 0.50 at 600 s, 0.65 at 1000 s.
  EXPECT_GT(checking.time(), trusting.time() + 300.0);
  EXPECT_GT(MappedOrPredictedNow(checking, reachable), trusted + 0.05);
}

}  // namespace
}  // namespace pslam
