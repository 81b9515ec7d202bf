#pragma once
// A hypothesis h (P-SLAM paper, section III-C and IV-B): the predicted states of the unexplored
// cells around an exploration target, copied from a similar region of the built map, plus what the
// caller later learns about it (validation V(.), hit ratio of eq. 23, Psi against the real map).
#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/map_raster.hpp"

namespace pslam {

struct HypothesisCell {
  Eigen::Vector2i cell{0, 0};  // index in the grid the hypothesis was predicted for
  bool occupied = false;       // predicted state: occupied, else free
};

struct Hypothesis {
  enum class Status { kPending, kConfirmed, kRefuted, kExpired };

  int id = 0;                           // unique per StructurePredictor, from 1
  double time = 0.0;                    // the caller's timestamp of the request
  Eigen::Vector2i target_cell{0, 0};    // f: the frontier cell the prediction was requested for
  Eigen::Vector2i reference_cell{0, 0}; // f': the reference map's cell that Gamma carries onto f
  // The map the reference came from: empty for the map being built, else a library map's id
  // (LibraryMap::id). reference_cell and reference_control_point are in that map's frame.
  std::string reference_map;
  // Gamma of eq. 2 in map metres: rotate by theta about reference_control_point (P2), then
  // translate by 'translation' = P1 - P2. ReferenceToTarget() gives it as a Pose2D.
  double theta = 0.0;                  // radians
  Eigen::Vector2d translation{0.0, 0.0};
  Eigen::Vector2d target_control_point{0.0, 0.0};     // P1, metres
  Eigen::Vector2d reference_control_point{0.0, 0.0};  // P2, metres
  double psi = 0.0;                    // eq. 5 between S_f and the aligned reference, explored part
  double area_m2 = 0.0;                // area predicted when generated (TakeExplored leaves it)
  // Cells that were never observed when the hypothesis was made, each with the state of the
  // aligned reference cell; cells whose reference was unknown or undecided are not predicted.
  std::vector<HypothesisCell> cells;
  // Cells of S_f observed but still undecided (CellState::kUncertain), each with the aligned
  // reference's state. The filter's maps already hold evidence there, so they do not weigh the
  // particles; they count only for exploration (coverage and the merged map) until decided.
  std::vector<HypothesisCell> undecided_cells;
  Status status = Status::kPending;    // set by the caller
  double hit_ratio = std::numeric_limits<double>::quiet_NaN();     // eq. 23, filled by the caller
  double psi_observed = std::numeric_limits<double>::quiet_NaN();  // ObservedSimilarity, by the caller
};

// Gamma as a rigid transform in map metres: a reference point x maps to ReferenceToTarget(h) * x.
Pose2D ReferenceToTarget(const Hypothesis& hypothesis);

// Moves a hypothesis with its map when a loop closure corrects the map by `move` (new frame from
// old): its cells (nearest cell), target cell and P1, and the reference cell and P2 when they
// are in that map (reference_map empty); a library reference stays and theta turns instead.
void MoveHypothesis(Hypothesis& hypothesis, const Pose2D& move, double resolution);

// Psi (eq. 5, occupied cells only, same tolerance as the search) between the hypothesis and
// 'later_map' over the hypothesis cells observed since it was made and decided there (occupied or
// free; a cell seen once or twice may still be uncertain, which is no evidence either way): how
// right the prediction turned out. A predicted wall counts as matched by a mapped one within the
// tolerance also just outside the hypothesis, as in the search. NaN when none of its cells has
// been observed yet; 0 when they have been but neither side has an occupied cell among them. Call
// it before TakeExplored, which drops those cells.
double ObservedSimilarity(const Hypothesis& hypothesis, const OccupancyGrid& later_map,
                          const CellStateThresholds& thresholds = {}, int tolerance_cells = 1);

// Moves the cells for which 'keep' is false out of 'cells', keeping the order of both parts, and
// returns them.
template <typename Keep>
std::vector<HypothesisCell> TakeCellsUnless(std::vector<HypothesisCell>& cells, Keep keep) {
  const auto gone = std::stable_partition(cells.begin(), cells.end(), keep);
  std::vector<HypothesisCell> taken(gone, cells.end());
  cells.erase(gone, cells.end());
  return taken;
}

// The same over a hypothesis's cells and undecided cells alike.
template <typename Keep>
std::vector<HypothesisCell> TakeCellsUnless(Hypothesis& hypothesis, Keep keep) {
  std::vector<HypothesisCell> taken = TakeCellsUnless(hypothesis.cells, keep);
  std::vector<HypothesisCell> undecided = TakeCellsUnless(hypothesis.undecided_cells, keep);
  taken.insert(taken.end(), undecided.begin(), undecided.end());
  return taken;
}

// The validation model V(.) of eq. 20: takes the cells that 'map' has observed since (any value
// but OccupancyGrid::kUnknown) out of the hypothesis, so that it only ever speaks for unexplored
// space, and returns them.
std::vector<HypothesisCell> TakeExplored(Hypothesis& hypothesis, const OccupancyGrid& map);
// Likewise for undecided_cells: takes out those 'map' has since decided, and returns them.
std::vector<HypothesisCell> TakeDecided(Hypothesis& hypothesis, const OccupancyGrid& map,
                                        const CellClassifier& classify);

}  // namespace pslam
