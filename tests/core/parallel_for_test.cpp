#include "pslam/common/parallel_for.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

namespace pslam {
namespace {

// A throwing worker slice must not terminate the process, and the caller must not return while
// another slice still runs the body (whose captures live on the caller's stack).
TEST(ThreadPool, ExceptionInAWorkerSliceReachesTheCallerAfterEverySliceEnded) {
  ThreadPool pool(4);
  std::atomic<int> running{0}, finished{0};
  const int n = 40;
  try {
    pool.ParallelFor(n, [&](int i) {
      ++running;
      if (i == n - 1) throw std::runtime_error("last index");  // the last slice belongs to a worker
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      ++finished;
      --running;
    });
    FAIL() << "the exception was swallowed";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "last index");
  }
  EXPECT_EQ(running.load(), 1);  // only the throwing call is unfinished
  EXPECT_EQ(finished.load(), n - 1);
  // The pool still works afterwards.
  std::vector<int> out(100, 0);
  pool.ParallelFor(100, [&](int i) { out[static_cast<std::size_t>(i)] = i; });
  for (int i = 0; i < 100; ++i) EXPECT_EQ(out[static_cast<std::size_t>(i)], i);
}

TEST(ThreadPool, ExceptionInTheCallersSliceWaitsForTheWorkers) {
  ThreadPool pool(2);
  std::atomic<int> finished{0};
  const int n = 20;
  EXPECT_THROW(pool.ParallelFor(n,
                                [&](int i) {
                                  if (i == 0) throw std::bad_alloc();  // index 0: the caller's slice
                                  std::this_thread::sleep_for(std::chrono::milliseconds(5));
                                  ++finished;
                                }),
               std::bad_alloc);
  EXPECT_EQ(finished.load(), n / 2);  // the worker's whole slice ran to its end before the rethrow
}

TEST(ThreadPool, EverySliceThrowingRethrowsOneException) {
  ThreadPool pool(3);
  for (int round = 0; round < 20; ++round) {
    EXPECT_THROW(pool.ParallelFor(9, [](int) { throw std::runtime_error("all"); }), std::runtime_error);
  }
}

}  // namespace
}  // namespace pslam
