#pragma once
// Runs predictions on one worker thread so that the particle filter never waits for them (the
// paper runs the predictor in its own thread for the same reason, section V-B). One request at a
// time: a request made while one is running is dropped, since a prediction for a target that is
// already out of date is worth less than the filter's time. The newest result waits in a single
// slot until polled.
#include <Eigen/Core>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <thread>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/hypothesis.hpp"
#include "pslam/predict/predictor_options.hpp"
#include "pslam/predict/structure_predictor.hpp"

namespace pslam {

struct AsyncPredictorStats {
  std::uint64_t accepted = 0;         // requests started
  std::uint64_t rejected = 0;         // requests dropped because one was running
  std::uint64_t completed = 0;        // predictions finished, with or without a hypothesis
  std::uint64_t hypotheses = 0;       // of which produced a hypothesis
  std::uint64_t results_replaced = 0; // hypotheses overwritten before TakeResult() took them
  double last_ms = 0.0;               // wall time of the last prediction on the worker
  double max_ms = 0.0;
  PredictionReport last_report;       // of the last prediction (default with a custom function)
  PredictorStats outcomes;            // counts per outcome so far (empty with a custom function)
};

class AsyncPredictor {
 public:
  using PredictFunction =
      std::function<std::optional<Hypothesis>(const OccupancyGrid&, const Eigen::Vector2i&, double, std::stop_token)>;

  // Throws std::invalid_argument if 'options' is invalid (see StructurePredictor); 'library' is
  // searched too (StructurePredictor).
  explicit AsyncPredictor(const PredictorOptions& options = {}, MapLibrary library = {});
  // Visible for testing: runs 'predict' instead of a StructurePredictor.
  explicit AsyncPredictor(PredictFunction predict);
  // Asks a running prediction to stop at its next check and joins the worker.
  ~AsyncPredictor();

  AsyncPredictor(const AsyncPredictor&) = delete;
  AsyncPredictor& operator=(const AsyncPredictor&) = delete;

  // Starts predicting 'target' in 'snapshot' (a copy of the best particle's map; copying a grid
  // copies tile pointers only). Returns false, and drops the request, if a prediction is running.
  // Never blocks beyond a short mutex.
  bool Request(OccupancyGrid snapshot, Eigen::Vector2i target, double time);
  // The newest hypothesis not yet taken, if any; never blocks beyond a short mutex.
  std::optional<Hypothesis> TakeResult();
  // True from an accepted Request() until its prediction has finished.
  bool busy() const;
  AsyncPredictorStats stats() const;

 private:
  struct Job {
    OccupancyGrid map;
    Eigen::Vector2i target;
    double time;
  };
  void Work(std::stop_token stop);

  std::unique_ptr<StructurePredictor> predictor_;  // used by the worker only; null with a custom function
  PredictFunction predict_;
  mutable std::mutex mutex_;
  std::condition_variable_any wake_;
  std::optional<Job> job_;
  bool busy_ = false;
  std::optional<Hypothesis> result_;
  AsyncPredictorStats stats_;
  // Last member: the worker starts after everything it uses exists, and is stopped and joined
  // first on destruction.
  std::jthread worker_;
};

}  // namespace pslam
