#include "pslam/predict/async_predictor.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <utility>

namespace pslam {

AsyncPredictor::AsyncPredictor(const PredictorOptions& options, MapLibrary library)
    : predictor_(std::make_unique<StructurePredictor>(options, std::move(library))),
      predict_([p = predictor_.get()](const OccupancyGrid& map, const Eigen::Vector2i& target, double time,
                                      std::stop_token stop) { return p->Predict(map, target, time, std::move(stop)); }),
      worker_([this](std::stop_token stop) { Work(std::move(stop)); }) {}

AsyncPredictor::AsyncPredictor(PredictFunction predict)
    : predict_(std::move(predict)), worker_([this](std::stop_token stop) { Work(std::move(stop)); }) {}

AsyncPredictor::~AsyncPredictor() {
  // std::jthread would do this in its own destructor; spelled out because the order matters: the
  // worker must be gone before the members it uses are destroyed.
  worker_.request_stop();
  if (worker_.joinable()) worker_.join();
}

bool AsyncPredictor::Request(OccupancyGrid snapshot, Eigen::Vector2i target, double time) {
  {
    std::lock_guard lock(mutex_);
    if (busy_) {
      ++stats_.rejected;
      return false;
    }
    busy_ = true;
    ++stats_.accepted;
    job_.emplace(Job{std::move(snapshot), target, time});
  }
  wake_.notify_one();
  return true;
}

std::optional<Hypothesis> AsyncPredictor::TakeResult() {
  std::lock_guard lock(mutex_);
  return std::exchange(result_, std::nullopt);
}

bool AsyncPredictor::busy() const {
  std::lock_guard lock(mutex_);
  return busy_;
}

AsyncPredictorStats AsyncPredictor::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

void AsyncPredictor::Work(std::stop_token stop) {
  while (true) {
    std::optional<Job> job;
    {
      std::unique_lock lock(mutex_);
      if (!wake_.wait(lock, stop, [this] { return job_.has_value(); })) return;  // stop requested
      job = std::exchange(job_, std::nullopt);
    }
    const auto start = std::chrono::steady_clock::now();
    std::optional<Hypothesis> result;
    try {
      result = predict_(job->map, job->target, job->time, stop);
    } catch (const std::exception&) {
      // A prediction is a guess the filter can do without; on this thread the exception would
      // terminate the process.
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    // The snapshot's tiles are released here, on the worker, before the result is published.
    job.reset();
    std::lock_guard lock(mutex_);
    ++stats_.completed;
    stats_.last_ms = ms;
    stats_.max_ms = std::max(stats_.max_ms, ms);
    if (predictor_) {
      stats_.last_report = predictor_->last_report();
      stats_.outcomes = predictor_->stats();
    }
    if (result) {
      ++stats_.hypotheses;
      if (result_) ++stats_.results_replaced;
      result_ = std::move(result);
    }
    busy_ = false;
  }
}

}  // namespace pslam
