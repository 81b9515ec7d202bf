#pragma once
// Every tunable of the environmental-structure predictor, with its default, in one place.
#include <optional>
#include <string>

#include "pslam/predict/features.hpp"
#include "pslam/predict/map_raster.hpp"

namespace pslam {

struct PredictorOptions {
  // d of the paper: S_f is the square of d_s x d_s cells centred on the target f, d_s =
  // ceil(d / resolution) (eq. 5). The paper draws a circle of diameter d (Fig. 1) but sums eq. 5
  // over a square; we keep the square, which is also the image the search works on.
  double region_size_m = 10.0;
  // The control point P1 is the corner nearest to f within this range; none, no prediction.
  double control_point_range_m = 3.0;
  // Reference corners closer than this to P1 are the target's own neighbourhood (f' != f in
  // eq. 1): pairing with them would "predict" S_f from itself shifted by a few cells.
  double min_reference_distance_m = 2.0;
  // The search bound the paper suggests (section III-A, "a fixed searching bound"): at most this
  // many reference corners, the strongest corner responses first, each tried at four angles.
  int max_reference_corners = 200;
  // Library maps searched besides the map being built (library_map.hpp), each with at most
  // max_reference_corners of its strongest corners: this many at most, the first given.
  int max_library_maps = 4;
  // Reference corners are taken within this distance of f, and features are extracted only on
  // the window that covers them and their regions, so a prediction costs the same in a 10 km^2
  // map as in a building wing.
  double search_radius_m = 50.0;
  // Psi needed for a hypothesis. The paper validates 0.4 to 0.7 and recommends 0.7 without prior
  // knowledge of the environment (section III-C); values outside that range are rejected.
  double similarity_threshold = 0.7;
  // Psi is a ratio: over a few cells of wall, one matching wall piece scores as high as a whole
  // matching room (on random polygons, a 1 m stub matched at Psi = 0.72). The explored part of
  // S_f must hold at least this much structure (occupied cells x resolution, about the length of
  // thin walls) for a prediction to be attempted.
  double min_structure_m = 4.0;
  // One-cell tolerance of the similarity measure (see similarity.hpp); 0 is eq. 5 exactly.
  int tolerance_cells = 1;
  // The best few alignments are refined by a small search over theta (+-2 steps of the angle that
  // moves the region's edge by one cell) and P1 (+-1 cell): the corner angles come from Hough
  // lines and the corners are located to about a cell, which at 5 m from P1 is already worth a
  // cell or two of misalignment. The paper names a better alignment as future work (section VI).
  int refined_candidates = 3;  // 0: no refinement
  // Coarse to fine: every alignment is first scored on a fixed pseudo-random quarter of the
  // explored cells of S_f (RegionMatcher::CoarsePsi, an estimate of the same ratio), and only the
  // best coarse_rescored are scored on all of them before the refinement. Scoring hundreds of
  // alignments was half of a prediction on an Intel-sized map. 0: score every alignment exactly.
  int coarse_rescored = 16;
  // Ambiguity (our addition; the paper takes the best match): in a building of look-alike rooms,
  // several references fit the explored part of S_f about equally well and disagree on the part to
  // predict, e.g. where the next door is. When an alignment within ambiguity_margin of the best
  // Psi predicts the unexplored cells with Psi below ambiguity_agreement against the best one's
  // prediction, the evidence does not single out a structure and no hypothesis is made. Repeated
  // identical structure (the maze) agrees and passes. ambiguity_margin 0: off. Measured on the
  // office (seeds 1-3, hypotheses with Psi >= 0.4 against the final map): off 51.6 %, 0.05/0.5
  // 57.8 % on seed 1 alone, 0.1/0.6 66.1 %, 0.15/0.7 58.0 % (fewer hypotheses, 57 on average,
  // better against the true world but not against the final map).
  double ambiguity_margin = 0.1;
  double ambiguity_agreement = 0.6;
  CellStateThresholds states;
  FeatureOptions features;
};

// nullopt when 'options' is usable, else a message naming the first offending field.
std::optional<std::string> ValidatePredictorOptions(const PredictorOptions& options);

}  // namespace pslam
