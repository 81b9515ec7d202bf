#pragma once
// How long one structure prediction takes as the map grows (the paper runs the predictor beside
// the filter and needs it to keep up, Sec. V-B). Maps of growing extent are made by cropping a
// larger map, and predictions are timed at frontier targets of each crop, as an explorer would
// ask for them.
#include <Eigen/Core>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/predictor_options.hpp"

namespace pslam {

// The cells of 'map' inside 'box' (inclusive); everything else unknown.
OccupancyGrid CropMap(const OccupancyGrid& map, const CellBox& box);

// Up to 'count' prediction targets on the frontier clusters of 'map' (largest first): with more
// clusters than 'count', each of evenly spaced clusters gives its cell nearest the centroid; with
// fewer, each cluster gives that cell and then cells spread along it, in turn, until 'count'.
std::vector<Eigen::Vector2i> FrontierTargets(const OccupancyGrid& map, int count);

// Wall time depends on what else the machine runs; the CPU time of the process (the predictor and
// any OpenCV worker threads) is what a prediction costs. Both are kept.
struct LatencyStats {
  int predictions = 0;
  int hypotheses = 0;
  int searched = 0;            // predictions that got as far as the alignment search
  std::vector<double> ms;      // wall time of each prediction, in target order
  std::vector<double> cpu_ms;  // CPU time of each
  std::vector<double> best_psi;  // Psi of the best alignment of each (0 when none was searched)
  double median_ms = 0.0, p95_ms = 0.0, max_ms = 0.0;
  double cpu_median_ms = 0.0, cpu_p95_ms = 0.0, cpu_max_ms = 0.0;
  // CPU time over the searched predictions only: the others stop early (no corner near the
  // target, too little structure) and would make the median look better than a real prediction.
  double searched_cpu_median_ms = 0.0;
  double searched_cpu_p95_ms = 0.0;
  // Share of the wall time spent rasterising and extracting features (the rest: alignment search).
  double feature_share = 0.0;
};

// Runs one synchronous prediction per target on 'map' and times each (wall: StructurePredictor's
// own total_ms, rasterising, features, search and hypothesis; CPU: the process's CPU clock around
// the call, so nothing else may run in the process meanwhile). Throws std::invalid_argument if the
// predictor options are invalid.
LatencyStats MeasurePredictionLatency(const OccupancyGrid& map, const std::vector<Eigen::Vector2i>& targets,
                                      const PredictorOptions& options);

// The q-quantile (q in [0, 1]) by linear interpolation between order statistics; 0 when empty.
double Quantile(std::vector<double> values, double q);

}  // namespace pslam
