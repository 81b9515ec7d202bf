#pragma once
// The environmental-structure predictor of P-SLAM (Chang et al., IEEE T-RO 2007, sections II-A
// and III): given the best particle's map and the next exploration target f (a frontier cell),
// find a region of the built map that looks like the surroundings S_f of f and copy its structure
// into the unexplored cells of S_f.
//
//   1. Rasterise the search window around f into cell states (map_raster.hpp).
//   2. Extract lines (Hough) and corners (image gradients) with their wall directions (features.hpp).
//   3. Control point P1: the corner nearest to f within control_point_range_m; none, no prediction.
//      Nor without min_structure_m of walls in the explored part of S_f to compare.
//   4. For each reference corner P2 (at most max_reference_corners, strongest first, outside the
//      target neighbourhood) and each of the four theta = phi_i(P1) - phi_j(P2), build Gamma
//      (eq. 2, alignment.hpp) and evaluate Psi over the explored part of S_f (eq. 3-5,
//      region_matcher.hpp); refine the best few alignments locally.
//   5. The best alignment with Psi >= similarity_threshold yields a hypothesis: the aligned
//      reference states written into the cells of S_f that were never observed (section III-C),
//      and apart into those observed but undecided, for exploration only.
//
// Library maps (library_map.hpp): other maps of the site, searched in step 4 as well, each with at
// most max_reference_corners of its strongest corners; a hypothesis names the map its reference
// came from. Their features are computed once, when the library map is made, not here. The same
// acceptance rules (threshold, ambiguity) apply to all candidates together.
//
// Bound on the work per prediction, whatever the size of the maps: feature extraction on a window
// of at most (2 (search_radius_m + region_size_m / sqrt(2) + control_point_range_m) / resolution)^2
// cells of the map being built, then at most 4 * max_reference_corners * (1 + L) + 44 *
// refined_candidates alignments, L = the library maps (at most max_library_maps), each costing
// one lookup per explored cell of S_f (at most ceil(region_size_m / resolution)^2), plus one
// listing of S_f per map searched and one exact Psi per refined candidate. With the defaults at
// 5 cm: a 2405^2-cell window and 932 alignments of at most 200^2 cells without a library, 4132
// with four library maps.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <stop_token>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/hypothesis.hpp"
#include "pslam/predict/library_map.hpp"
#include "pslam/predict/predictor_options.hpp"

namespace pslam {

// What the last Predict() call found, whether or not it produced a hypothesis.
struct PredictionReport {
  enum class Outcome {
    kHypothesis,         // a hypothesis was returned
    kNoControlPoint,     // no corner within control_point_range_m of f
    kTooLittleStructure, // the explored part of S_f has less than min_structure_m of walls
    kNoReferenceCorner,  // no corner to pair with outside the target neighbourhood
    kBelowThreshold,     // the best Psi stayed below similarity_threshold
    kAmbiguous,          // a near-equal alignment predicts the unexplored part differently
    kNothingToPredict,   // a match, but S_f has no unexplored cell the reference knows
    kCancelled,          // the stop token fired
  };
  Outcome outcome = Outcome::kNoControlPoint;
  double best_psi = 0.0;       // Psi of the best alignment, exact (similarity.hpp)
  int corners = 0;             // corners with at least one wall direction in the window
  int reference_corners = 0;   // corners paired with P1
  int alignments = 0;          // Gamma evaluated, refinement included
  double features_ms = 0.0;    // rasterising and feature extraction
  double search_ms = 0.0;      // alignment search, refinement and hypothesis
  double total_ms = 0.0;
};

struct PredictorStats {
  std::uint64_t predictions = 0;  // Predict() calls
  std::uint64_t hypotheses = 0;
  std::uint64_t no_control_point = 0;
  std::uint64_t too_little_structure = 0;
  std::uint64_t no_reference_corner = 0;
  std::uint64_t below_threshold = 0;
  std::uint64_t ambiguous = 0;
  std::uint64_t nothing_to_predict = 0;
  std::uint64_t cancelled = 0;
  double last_ms = 0.0;
  double max_ms = 0.0;
  double total_ms = 0.0;
};

// Not thread-safe: one instance per thread (AsyncPredictor owns one on its worker). Its only state
// is the hypothesis id counter and the statistics; Predict() is otherwise a pure function of its
// arguments and the options.
class StructurePredictor {
 public:
  // Throws std::invalid_argument with ValidatePredictorOptions' message if 'options' is invalid.
  // 'library': maps searched besides the one predicted in (the first max_library_maps; those of
  // another resolution are skipped), made with the same options.
  explicit StructurePredictor(const PredictorOptions& options = {}, MapLibrary library = {});

  // Predicts the unexplored surroundings of 'target' (a cell of 'map', normally a frontier cell)
  // from the rest of 'map' and the library maps. nullopt when there is no control point, too little structure, no
  // match above the threshold or nothing to predict (last_report() says which), or when 'stop'
  // is requested. 'time' is
  // copied into the hypothesis.
  std::optional<Hypothesis> Predict(const OccupancyGrid& map, const Eigen::Vector2i& target, double time,
                                    std::stop_token stop = {});

  const PredictionReport& last_report() const { return report_; }
  const PredictorStats& stats() const { return stats_; }
  const PredictorOptions& options() const { return options_; }
  const MapLibrary& library() const { return library_; }

 private:
  std::optional<Hypothesis> Run(const OccupancyGrid& map, const Eigen::Vector2i& target, double time,
                                const std::stop_token& stop);

  PredictorOptions options_;
  CellClassifier classify_;
  MapLibrary library_;
  int next_id_ = 1;
  PredictionReport report_;
  PredictorStats stats_;
};

}  // namespace pslam
