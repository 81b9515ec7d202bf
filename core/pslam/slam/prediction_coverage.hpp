#pragma once
// Which unknown or undecided cells the accepted hypotheses cover, and which of them they predict
// as walls: what skip-predicted exploration asks (PSlam::IsCovered, PSlam::IsPredictedWall).
//
// Hypotheses overlap (each new target predicts a 10 m square around it), so a cell counts the
// hypotheses covering it: withdrawing one hypothesis must not uncover cells another still covers.
#include <Eigen/Core>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/hypothesis.hpp"

namespace pslam {

class PredictionCoverage {
 public:
  explicit PredictionCoverage(double resolution = 0.05);

  void Add(const std::vector<HypothesisCell>& cells);
  // 'cells' must have been added before (a hypothesis's cells, or some of them).
  void Remove(const std::vector<HypothesisCell>& cells);

  bool Covered(const Eigen::Vector2i& cell) const { return covering_.IsKnown(cell.x(), cell.y()); }
  bool PredictedWall(const Eigen::Vector2i& cell) const { return walls_.IsKnown(cell.x(), cell.y()); }
  // The covered cells: known exactly where Covered() holds (for walking them tile by tile).
  const OccupancyGrid& covering() const { return covering_; }

 private:
  // Counts per cell (unknown: zero), in grids for their sparse tiled storage.
  static void Increment(OccupancyGrid& counts, const Eigen::Vector2i& cell);
  static void Decrement(OccupancyGrid& counts, const Eigen::Vector2i& cell);

  OccupancyGrid covering_;  // hypotheses covering the cell
  OccupancyGrid walls_;     // of which predict it occupied
};

}  // namespace pslam
