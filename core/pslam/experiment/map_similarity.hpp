#pragma once
// Scoring predictions and maps against a reference map (the simulator's true world, or the map
// built at the end of a run) with the paper's similarity measure Psi (eq. 5: occupied cells only,
// with the predictor's one-cell tolerance), as the paper scores its hypotheses (Sec. V-A2).
#include <functional>
#include <vector>

#include "pslam/common/pose2d.hpp"

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/hypothesis.hpp"
#include "pslam/predict/map_raster.hpp"
#include "pslam/slam/pslam.hpp"

namespace pslam {

struct SimilarityOptions {
  CellStateThresholds states;
  int tolerance_cells = 1;
};

// Psi between predicted cells and 'reference', over the predicted cells the reference knows. NaN
// when it knows none of them; 0 when neither side has an occupied cell among them.
double PredictionSimilarity(const std::vector<HypothesisCell>& predicted, const OccupancyGrid& reference,
                            const SimilarityOptions& options = {});

// Cells moved by a rigid transform (cell centre to cell centre), e.g. from the SLAM map frame into
// the world frame; cells that land on the same cell are kept once, the first one.
std::vector<HypothesisCell> TransformCells(const std::vector<HypothesisCell>& cells, const Pose2D& transform,
                                           double resolution);

// The predicted cells of P-SLAM's merged map: those of the hypotheses not refuted that the
// best map still does not know or has not decided (what MergedMap() adds to the built map), each
// hypothesis's cells moved by to_reference(its id) when given (see TransformCells); a cell
// predicted twice counts once.
std::vector<HypothesisCell> MergedPredictedCells(const PSlam& slam,
                                                 const std::function<Pose2D(int id)>& to_reference = {});

// Psi between a built map and 'reference' over the cells the built map knows: how well the walls
// it mapped sit where the reference has them.
double BuiltMapSimilarity(const OccupancyGrid& built, const OccupancyGrid& reference,
                          const SimilarityOptions& options = {});

// The share of the reference's free cells that 'built' knows or 'predicted' (cells of the
// reference's lattice) covers: how much of the world a run left neither mapped nor predicted. A
// skip-predicted run is only shorter for a reason if this stays near the full-coverage run's.
double MappedOrPredictedFraction(const OccupancyGrid& reference, const OccupancyGrid& built,
                                 const std::vector<HypothesisCell>& predicted);

// The map and predicted cells on cells 'factor' times as large (factor x factor pooled): a pooled
// cell is occupied if any of its cells is, else free if any is known. Scoring on the paper's 0.1 m
// cells with tolerance 0 is eq. 5 exactly as the paper took it.
OccupancyGrid PoolGrid(const OccupancyGrid& map, int factor);
std::vector<HypothesisCell> PoolCells(const std::vector<HypothesisCell>& cells, int factor);

// Area of the cells a map knows, in square metres.
double KnownArea(const OccupancyGrid& map);

}  // namespace pslam
