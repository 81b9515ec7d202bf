#include "pslam/predict/async_predictor.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace pslam {
namespace {

using Clock = std::chrono::steady_clock;

// Polls 'done' for up to five seconds; a stuck worker fails the test instead of hanging it.
template <typename Predicate>
bool WaitFor(Predicate done) {
  const auto deadline = Clock::now() + std::chrono::seconds(5);
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

// A prediction that holds the worker until the test releases it (or the predictor stops it),
// so that "a request is running" is a fact of the test, not a race.
struct GatedPrediction {
  std::atomic<bool> release{false};
  std::atomic<int> started{0};
  std::atomic<bool> saw_stop{false};
  bool produce = true;

  AsyncPredictor::PredictFunction Function() {
    return [this](const OccupancyGrid&, const Eigen::Vector2i& target, double time,
                  std::stop_token stop) -> std::optional<Hypothesis> {
      ++started;
      while (!release && !stop.stop_requested()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      saw_stop = stop.stop_requested();
      if (!produce) return std::nullopt;
      Hypothesis h;
      h.id = started;
      h.target_cell = target;
      h.time = time;
      return h;
    };
  }
};

TEST(AsyncPredictor, PollsWithoutBlockingAndRejectsAConcurrentRequest) {
  GatedPrediction gate;
  AsyncPredictor async(gate.Function());
  ASSERT_TRUE(async.Request(OccupancyGrid(0.05), {3, 4}, 1.0));
  EXPECT_TRUE(async.busy());
  const auto start = Clock::now();
  // The prediction is held until released below, so a blocking poll would never return; the
  // bound is loose only to survive a loaded machine.
  EXPECT_FALSE(async.TakeResult().has_value());
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 1.0);
  EXPECT_FALSE(async.Request(OccupancyGrid(0.05), {5, 6}, 2.0));  // dropped, not queued
  EXPECT_EQ(async.stats().rejected, 1u);

  gate.release = true;
  ASSERT_TRUE(WaitFor([&] { return !async.busy(); }));
  const auto h = async.TakeResult();
  ASSERT_TRUE(h.has_value());
  EXPECT_EQ(h->target_cell, Eigen::Vector2i(3, 4));  // the first request's, not the dropped one's
  EXPECT_DOUBLE_EQ(h->time, 1.0);
  EXPECT_EQ(gate.started, 1);
  const AsyncPredictorStats stats = async.stats();
  EXPECT_EQ(stats.accepted, 1u);
  EXPECT_EQ(stats.completed, 1u);
  EXPECT_EQ(stats.hypotheses, 1u);
  EXPECT_GT(stats.last_ms, 0.0);

  // Free again: the next request is accepted.
  EXPECT_TRUE(async.Request(OccupancyGrid(0.05), {7, 8}, 3.0));
  ASSERT_TRUE(WaitFor([&] { return !async.busy(); }));
  EXPECT_EQ(async.TakeResult()->target_cell, Eigen::Vector2i(7, 8));
}

TEST(AsyncPredictor, KeepsOnlyTheNewestResult) {
  GatedPrediction gate;
  gate.release = true;
  AsyncPredictor async(gate.Function());
  ASSERT_TRUE(async.Request(OccupancyGrid(0.05), {1, 1}, 1.0));
  ASSERT_TRUE(WaitFor([&] { return !async.busy(); }));
  ASSERT_TRUE(async.Request(OccupancyGrid(0.05), {2, 2}, 2.0));
  ASSERT_TRUE(WaitFor([&] { return !async.busy(); }));
  const auto h = async.TakeResult();
  ASSERT_TRUE(h.has_value());
  EXPECT_DOUBLE_EQ(h->time, 2.0);
  EXPECT_FALSE(async.TakeResult().has_value());
  EXPECT_EQ(async.stats().results_replaced, 1u);
}

TEST(AsyncPredictor, PredictionWithoutHypothesisCompletesEmpty) {
  GatedPrediction gate;
  gate.release = true;
  gate.produce = false;
  AsyncPredictor async(gate.Function());
  ASSERT_TRUE(async.Request(OccupancyGrid(0.05), {1, 1}, 1.0));
  ASSERT_TRUE(WaitFor([&] { return async.stats().completed == 1u; }));
  EXPECT_FALSE(async.busy());
  EXPECT_FALSE(async.TakeResult().has_value());
  EXPECT_EQ(async.stats().hypotheses, 0u);
}

TEST(AsyncPredictor, DestructorStopsARunningPrediction) {
  GatedPrediction gate;  // never released: only the stop token ends the prediction
  const auto start = Clock::now();
  {
    AsyncPredictor async(gate.Function());
    ASSERT_TRUE(async.Request(OccupancyGrid(0.05), {1, 1}, 1.0));
    ASSERT_TRUE(WaitFor([&] { return gate.started == 1; }));
  }
  EXPECT_TRUE(gate.saw_stop);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 2.0);
}

TEST(AsyncPredictor, IdleShutdownAndInvalidOptions) {
  { AsyncPredictor idle; }  // joins a worker that never had work
  PredictorOptions options;
  options.similarity_threshold = 0.9;
  EXPECT_THROW(AsyncPredictor{options}, std::invalid_argument);
}

}  // namespace
}  // namespace pslam
