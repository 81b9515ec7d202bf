#include "pslam/predict/hypothesis.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "pslam/predict/alignment.hpp"
#include "pslam/predict/similarity.hpp"

namespace pslam {
namespace {

}  // namespace

Pose2D ReferenceToTarget(const Hypothesis& hypothesis) {
  return AlignmentTransform(hypothesis.target_control_point, hypothesis.reference_control_point, hypothesis.theta);
}

void MoveHypothesis(Hypothesis& h, const Pose2D& move, double resolution) {
  const OccupancyGrid lattice(resolution);
  const auto cell = [&](const Eigen::Vector2i& c) { return lattice.WorldToCell(move * lattice.CellCenter(c)); };
  for (HypothesisCell& c : h.cells) c.cell = cell(c.cell);
  for (HypothesisCell& c : h.undecided_cells) c.cell = cell(c.cell);
  h.target_cell = cell(h.target_cell);
  h.target_control_point = move * h.target_control_point;
  if (h.reference_map.empty()) {
    // Gamma conjugated by the move: the same rotation, between the moved control points.
    h.reference_cell = cell(h.reference_cell);
    h.reference_control_point = move * h.reference_control_point;
  } else {
    // Gamma followed by the move: the library map stays where it is.
    h.theta = NormalizeAngle(h.theta + move.theta);
  }
  h.translation = h.target_control_point - h.reference_control_point;
}

double ObservedSimilarity(const Hypothesis& hypothesis, const OccupancyGrid& later_map,
                          const CellStateThresholds& thresholds, int tolerance_cells) {
  CellBox box;
  for (const HypothesisCell& c : hypothesis.cells) {
    if (later_map.IsKnown(c.cell.x(), c.cell.y())) box.Extend(c.cell);
  }
  if (box.empty()) return std::numeric_limits<double>::quiet_NaN();
  // The observation plays S_f and the prediction the aligned reference. They are compared over the
  // hypothesis cells the later map has decided (a cell seen once or twice may still be uncertain,
  // which is no evidence either way), but each is dilated over all it holds: the later map around
  // those cells too. Predicted walls mostly run along the edge of what was explored, and a wall
  // mapped one cell outside the hypothesis is as close as one mapped one cell inside it.
  const Eigen::Vector2i margin = Eigen::Vector2i::Constant(std::max(0, tolerance_cells));
  const CellBox wide{box.min - margin, box.max + margin};
  const CellClassifier classify(thresholds);
  const CellRaster observed = RasterizeRegion(later_map, wide, classify);
  CellRaster predicted(wide.min, wide.width(), wide.height());
  for (const HypothesisCell& c : hypothesis.cells) {
    if (!predicted.Contains(c.cell)) continue;
    const Eigen::Vector2i local = c.cell - wide.min;
    predicted.Local(local.x(), local.y()) = c.occupied ? CellState::kOccupied : CellState::kFree;
  }
  std::vector<std::uint8_t> compared(predicted.cells.size());
  for (std::size_t i = 0; i < compared.size(); ++i) {
    const CellState seen = observed.cells[i];
    compared[i] = IsExplored(predicted.cells[i]) && (seen == CellState::kOccupied || seen == CellState::kFree);
  }
  return CountOverlap(observed, predicted, tolerance_cells, compared).Psi();
}

std::vector<HypothesisCell> TakeExplored(Hypothesis& hypothesis, const OccupancyGrid& map) {
  return TakeCellsUnless(hypothesis.cells, [&](const HypothesisCell& c) { return !map.IsKnown(c.cell.x(), c.cell.y()); });
}

std::vector<HypothesisCell> TakeDecided(Hypothesis& hypothesis, const OccupancyGrid& map,
                                        const CellClassifier& classify) {
  return TakeCellsUnless(hypothesis.undecided_cells, [&](const HypothesisCell& c) {
    return classify(map.At(c.cell.x(), c.cell.y())) == CellState::kUncertain;
  });
}

}  // namespace pslam
