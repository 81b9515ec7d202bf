#include "pslam/slam/prediction_coverage.hpp"

namespace pslam {

PredictionCoverage::PredictionCoverage(double resolution) : covering_(resolution), walls_(resolution) {}

void PredictionCoverage::Increment(OccupancyGrid& counts, const Eigen::Vector2i& cell) {
  OccupancyGrid::Cell& n = counts.MutableAt(cell.x(), cell.y());
  n = n == OccupancyGrid::kUnknown ? 1 : static_cast<OccupancyGrid::Cell>(n + 1);
}

void PredictionCoverage::Decrement(OccupancyGrid& counts, const Eigen::Vector2i& cell) {
  const OccupancyGrid::Cell n = counts.At(cell.x(), cell.y());
  if (n == OccupancyGrid::kUnknown) return;
  if (n <= 1) counts.Forget(cell.x(), cell.y());
  else counts.MutableAt(cell.x(), cell.y()) = static_cast<OccupancyGrid::Cell>(n - 1);
}

void PredictionCoverage::Add(const std::vector<HypothesisCell>& cells) {
  for (const HypothesisCell& c : cells) {
    Increment(covering_, c.cell);
    if (c.occupied) Increment(walls_, c.cell);
  }
}

void PredictionCoverage::Remove(const std::vector<HypothesisCell>& cells) {
  for (const HypothesisCell& c : cells) {
    Decrement(covering_, c.cell);
    if (c.occupied) Decrement(walls_, c.cell);
  }
}

}  // namespace pslam
