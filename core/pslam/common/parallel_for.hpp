#pragma once
// A small fixed pool of worker threads for data-parallel loops over particles. Work is split into
// contiguous index ranges; results must not depend on which thread ran an index, which keeps runs
// deterministic for a seed.
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace pslam {

class ThreadPool {
 public:
  explicit ThreadPool(int threads = 0);  // 0: one per hardware thread
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }
  // Runs body(i) for i in [0, n); the calling thread takes part. Returns when all are done. If
  // body throws (on any thread), every slice still ends before the first exception is rethrown here.
  void ParallelFor(int n, const std::function<void(int)>& body);

 private:
  void WorkerLoop(int worker);
  void RunSlice(const std::function<void(int)>& body, int n, int slice);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  const std::function<void(int)>* body_ = nullptr;
  int n_ = 0;
  int generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;  // the first exception of the current loop
};

}  // namespace pslam
