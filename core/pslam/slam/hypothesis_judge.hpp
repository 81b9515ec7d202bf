#pragma once
// When and how a hypothesis is judged against what the robot has since observed of it.
//
// Psi (eq. 5) counts occupied cells only. Over an observed part holding a metre of wall it is
// noise: one wall piece a cell off scores 0, and a matching stub scores 1. Judged that early, the
// verdict disagreed with the truth for half of the hypotheses. So a hypothesis is judged only
// once enough of it has been seen (share of its cells) and that part holds enough structure to
// score: the predictor's own bar for S_f (min_structure_m), taken on whichever side has more
// walls there, so that predicted walls the laser finds missing still refute it. Before a
// refutation, a second look allows for the map having moved since the prediction
// (HypothesisJudgeOptions::registration_m).
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/hypothesis.hpp"
#include "pslam/predict/map_raster.hpp"
#include "pslam/slam/pslam_options.hpp"

namespace pslam {

struct ObservedEvidence {
  double observed_fraction = 0.0;  // of the hypothesis's cells, known in the map
  double predicted_walls_m = 0.0;  // occupied predicted cells among them x resolution
  double observed_walls_m = 0.0;   // occupied observed cells among them x resolution
  double psi = 0.0;                // ObservedSimilarity; NaN when nothing is observed yet
};

enum class Verdict { kUndecided, kConfirmed, kRefuted };

// 'original' is the hypothesis as generated (its cells never shrink).
ObservedEvidence GatherEvidence(const Hypothesis& original, const OccupancyGrid& map,
                                const CellStateThresholds& thresholds, int tolerance_cells);

Verdict Judge(const ObservedEvidence& evidence, const HypothesisJudgeOptions& options);

// The highest ObservedSimilarity of 'original' moved by a whole-cell shift other than none, of at
// most 'reach_cells' along each axis; NaN when no such shift reaches an observed cell.
double RegisteredSimilarity(const Hypothesis& original, const OccupancyGrid& map,
                            const CellStateThresholds& thresholds, int tolerance_cells, int reach_cells);

// Judge(), with the second look of HypothesisJudgeOptions::registration_m before a refutation.
// 'evidence' is GatherEvidence(original, map, ...).
Verdict JudgeOnMap(const Hypothesis& original, const ObservedEvidence& evidence, const OccupancyGrid& map,
                   const CellStateThresholds& thresholds, int tolerance_cells, const HypothesisJudgeOptions& options);

}  // namespace pslam
