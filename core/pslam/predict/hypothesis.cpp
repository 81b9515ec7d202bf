#include "pslam/predict/hypothesis.hpp"

#include <algorithm>

#include "pslam/predict/alignment.hpp"
#include "pslam/predict/similarity.hpp"

namespace pslam {
namespace {

// Moves the cells for which 'still' is false out of 'cells' (keeping the order of both parts).
template <typename Still>
std::vector<HypothesisCell> TakeUnless(std::vector<HypothesisCell>& cells, Still still) {
  const auto gone = std::stable_partition(cells.begin(), cells.end(), still);
  std::vector<HypothesisCell> taken(gone, cells.end());
  cells.erase(gone, cells.end());
  return taken;
}

}  // namespace

Pose2D ReferenceToTarget(const Hypothesis& hypothesis) {
  return AlignmentTransform(hypothesis.target_control_point, hypothesis.reference_control_point, hypothesis.theta);
}

double ObservedSimilarity(const Hypothesis& hypothesis, const OccupancyGrid& later_map,
                          const CellStateThresholds& thresholds, int tolerance_cells) {
  CellBox box;
  for (const HypothesisCell& c : hypothesis.cells) {
    if (later_map.IsKnown(c.cell.x(), c.cell.y())) box.Extend(c.cell);
  }
  if (box.empty()) return std::numeric_limits<double>::quiet_NaN();
  // Both rasters hold only the cells observed since: the observation plays S_f (its explored
  // part is exactly those cells), the prediction plays the aligned reference.
  const CellClassifier classify(thresholds);
  CellRaster observed(box.min, box.width(), box.height());
  CellRaster predicted(box.min, box.width(), box.height());
  for (const HypothesisCell& c : hypothesis.cells) {
    if (!observed.Contains(c.cell)) continue;
    const CellState state = classify(later_map.At(c.cell.x(), c.cell.y()));
    if (state != CellState::kOccupied && state != CellState::kFree) continue;  // not decided yet
    const Eigen::Vector2i local = c.cell - box.min;
    observed.Local(local.x(), local.y()) = state;
    predicted.Local(local.x(), local.y()) = c.occupied ? CellState::kOccupied : CellState::kFree;
  }
  return Similarity(observed, predicted, tolerance_cells);
}

std::vector<HypothesisCell> TakeExplored(Hypothesis& hypothesis, const OccupancyGrid& map) {
  return TakeUnless(hypothesis.cells, [&](const HypothesisCell& c) { return !map.IsKnown(c.cell.x(), c.cell.y()); });
}

std::vector<HypothesisCell> TakeDecided(Hypothesis& hypothesis, const OccupancyGrid& map,
                                        const CellClassifier& classify) {
  return TakeUnless(hypothesis.undecided_cells, [&](const HypothesisCell& c) {
    return classify(map.At(c.cell.x(), c.cell.y())) == CellState::kUncertain;
  });
}

}  // namespace pslam
