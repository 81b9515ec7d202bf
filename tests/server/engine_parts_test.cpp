// Engine parts without a server: the live tick token bucket and the exploration planner worker.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>

#include "engine/exploration_planner.hpp"
#include "engine/token_bucket.hpp"

namespace pslam::server {
namespace {

using std::chrono::milliseconds;

TEST(TokenBucketTest, AllowsABurstThenTheAverageRate) {
  const SteadyTime t0 = SteadyNow();
  TokenBucket bucket(10.0, 3.0, t0);
  // A full bucket: three ticks at once, the fourth waits for the refill (100 ms per token).
  EXPECT_TRUE(bucket.TryTake(t0));
  EXPECT_TRUE(bucket.TryTake(t0));
  EXPECT_TRUE(bucket.TryTake(t0));
  EXPECT_FALSE(bucket.TryTake(t0));
  EXPECT_EQ(bucket.NextToken(t0), t0 + milliseconds(100));
  EXPECT_FALSE(bucket.TryTake(t0 + milliseconds(99)));
  EXPECT_TRUE(bucket.TryTake(t0 + milliseconds(100)));
  // Over a long run of requests every 10 ms, no more than 10 per second (+ the burst) get through.
  int taken = 0;
  for (int i = 1; i <= 1000; ++i) taken += bucket.TryTake(t0 + milliseconds(100 + 10 * i)) ? 1 : 0;
  EXPECT_EQ(taken, 100);
  // Idle time saves up no more than the capacity.
  const SteadyTime later = t0 + std::chrono::seconds(60);
  int burst = 0;
  while (bucket.TryTake(later)) ++burst;
  EXPECT_EQ(burst, 3);
  EXPECT_EQ(bucket.NextToken(later + milliseconds(100)), later + milliseconds(100));
}

constexpr OccupancyGrid::Cell kFree = -2000;
constexpr OccupancyGrid::Cell kOccupied = 3000;

// A known 3 m x 3 m room with walls, open to unknown space on its right side (x = 3 m).
OccupancyGrid RoomOpenToTheRight() {
  OccupancyGrid grid(0.05);
  for (int y = -1; y <= 60; ++y) {
    for (int x = -1; x < 60; ++x) {
      const bool wall = x < 0 || y < 0 || y >= 60;
      grid.MutableAt(x, y) = wall ? kOccupied : kFree;
    }
  }
  return grid;
}

TEST(ExplorationPlannerTest, PlansOnTheWorkerAndDropsRequestsWhileBusy) {
  std::atomic<int> ready{0};
  ExplorationPlanner planner([&] { ++ready; });
  PlanRequest request{RoomOpenToTheRight(), PredictionCoverage(0.05), Pose2D(1.5, 1.5, 0.0), false, 12.5};
  ASSERT_TRUE(planner.Request(request));
  EXPECT_FALSE(planner.Request(request));  // one at a time
  planner.WaitIdle();
  EXPECT_EQ(ready.load(), 1);
  EXPECT_TRUE(planner.busy());             // until its result is taken
  EXPECT_FALSE(planner.Request(request));
  std::optional<PlanResult> result = planner.TakeResult();
  ASSERT_TRUE(result);
  EXPECT_FALSE(planner.TakeResult());
  EXPECT_FALSE(planner.busy());
  EXPECT_DOUBLE_EQ(result->time, 12.5);
  ASSERT_TRUE(result->target);
  EXPECT_NEAR(result->target->position.x(), 2.975, 0.1);  // the open side
  EXPECT_FALSE(result->target->path.empty());
  ASSERT_EQ(result->frontiers.size(), 1u);
  EXPECT_NEAR(result->frontiers[0][0], 2.975, 0.1);
}

TEST(ExplorationPlannerTest, SkipsFrontiersCoveredByPredictionsAndReportsDone) {
  PlanRequest request{RoomOpenToTheRight(), PredictionCoverage(0.05), Pose2D(1.5, 1.5, 0.0), true, 0.0};
  // Every unknown cell around the room is covered by a hypothesis of free space.
  std::vector<HypothesisCell> cells;
  for (int y = -60; y < 120; ++y) {
    for (int x = -60; x < 120; ++x) cells.push_back({{x, y}, false});
  }
  request.coverage.Add(cells);
  request.verify_predicted = false;
  const PlanResult result = Plan(request);
  EXPECT_FALSE(result.target);  // nothing left to explore
  EXPECT_EQ(result.skipped, 1);
  EXPECT_EQ(result.frontiers.size(), 1u);  // the frontier is still there, only skipped
  // Verifying (the default): the predicted frontier becomes the target.
  request.verify_predicted = true;
  const PlanResult verify = Plan(request);
  ASSERT_TRUE(verify.target);
  EXPECT_TRUE(verify.verifying);
}

}  // namespace
}  // namespace pslam::server
