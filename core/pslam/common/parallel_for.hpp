#pragma once
// A small fixed pool of worker threads for data-parallel loops over particles. Work is split into
// contiguous index ranges; results must not depend on which thread ran an index, which keeps runs
// deterministic for a seed.
#include <condition_variable>
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
  // Runs body(i) for i in [0, n); the calling thread takes part. Returns when all are done.
  void ParallelFor(int n, const std::function<void(int)>& body);

 private:
  void WorkerLoop(int worker);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  const std::function<void(int)>* body_ = nullptr;
  int n_ = 0;
  int generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
};

}  // namespace pslam
