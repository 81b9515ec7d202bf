#include "pslam/slam/hypothesis_judge.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pslam {

ObservedEvidence GatherEvidence(const Hypothesis& original, const OccupancyGrid& map,
                                const CellStateThresholds& thresholds, int tolerance_cells) {
  ObservedEvidence e;
  if (original.cells.empty()) return e;
  const CellClassifier classify(thresholds);
  int observed = 0, predicted_walls = 0, observed_walls = 0;
  for (const HypothesisCell& c : original.cells) {
    const OccupancyGrid::Cell value = map.At(c.cell.x(), c.cell.y());
    if (value == OccupancyGrid::kUnknown) continue;
    ++observed;
    predicted_walls += c.occupied;
    observed_walls += classify(value) == CellState::kOccupied;
  }
  e.observed_fraction = static_cast<double>(observed) / static_cast<double>(original.cells.size());
  e.predicted_walls_m = predicted_walls * map.resolution();
  e.observed_walls_m = observed_walls * map.resolution();
  e.psi = ObservedSimilarity(original, map, thresholds, tolerance_cells);
  return e;
}

Verdict Judge(const ObservedEvidence& e, const HypothesisJudgeOptions& options) {
  if (!std::isfinite(e.psi) || e.observed_fraction < options.judge_observed_fraction) return Verdict::kUndecided;
  // Once all of it is seen nothing more will come: judge on what there is.
  const bool complete = e.observed_fraction >= 1.0;
  if (!complete && std::max(e.predicted_walls_m, e.observed_walls_m) < options.min_structure_m) {
    return Verdict::kUndecided;
  }
  return e.psi >= options.confirm_psi ? Verdict::kConfirmed : Verdict::kRefuted;
}

double RegisteredSimilarity(const Hypothesis& original, const OccupancyGrid& map,
                            const CellStateThresholds& thresholds, int tolerance_cells, int reach_cells) {
  double best = std::numeric_limits<double>::quiet_NaN();
  Hypothesis moved;  // ObservedSimilarity reads only the cells
  moved.cells = original.cells;
  for (int dy = -reach_cells; dy <= reach_cells; ++dy) {
    for (int dx = -reach_cells; dx <= reach_cells; ++dx) {
      if (dx == 0 && dy == 0) continue;
      for (std::size_t i = 0; i < moved.cells.size(); ++i) {
        moved.cells[i].cell = original.cells[i].cell + Eigen::Vector2i(dx, dy);
      }
      const double psi = ObservedSimilarity(moved, map, thresholds, tolerance_cells);
      if (std::isnan(best) || psi > best) best = psi;
    }
  }
  return best;
}

Verdict JudgeOnMap(const Hypothesis& original, const ObservedEvidence& evidence, const OccupancyGrid& map,
                   const CellStateThresholds& thresholds, int tolerance_cells, const HypothesisJudgeOptions& options) {
  const Verdict verdict = Judge(evidence, options);
  const int reach = static_cast<int>(std::floor(options.registration_m / map.resolution() + 1e-9));
  if (verdict != Verdict::kRefuted || reach <= 0) return verdict;
  // evidence.psi is the unshifted Psi; only the shifts are left to try.
  const double shifted = RegisteredSimilarity(original, map, thresholds, tolerance_cells, reach);
  if (!(shifted > evidence.psi)) return verdict;
  ObservedEvidence registered = evidence;
  registered.psi = shifted;
  return Judge(registered, options);
}

}  // namespace pslam
