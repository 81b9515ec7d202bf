#pragma once
// Where the robot has seen a hypothesis wrong, the rest of it nearby is not trusted either.
//
// Rooms that repeat a plan still differ inside: a bed, a desk or a cupboard stands elsewhere. A
// hypothesis copied from another room then predicts floor where the robot finds the face of a
// block, and floor behind that face, where the block is; the judge (hypothesis_judge.hpp) weighs
// the whole hypothesis and keeps it when its walls are right. Such a contradiction says nothing of
// the hypothesis far away, but the cells around it, which the robot has not seen yet, are the rest
// of the same wrong piece: they are withdrawn (HypothesisJudgeOptions::local_refutation_radius_m).
#include <Eigen/Core>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/hypothesis.hpp"
#include "pslam/predict/map_raster.hpp"

namespace pslam {

// Cells of 'seen' (cells of 'original' the map has just observed) whose observed state contradicts
// the prediction: a wall observed where floor was predicted with no predicted wall within
// 'tolerance_cells', or floor observed where a wall was predicted with no observed wall within it
// (as Psi, eq. 5, allows). Undecided cells contradict nothing.
std::vector<Eigen::Vector2i> FindContradictions(const std::vector<HypothesisCell>& seen, const Hypothesis& original,
                                                const OccupancyGrid& map, const CellClassifier& classify,
                                                int tolerance_cells);

// Moves the cells of 'h' (predicted and undecided) within 'radius_cells' of any of 'points' out of
// it and returns them.
std::vector<HypothesisCell> TakeNear(Hypothesis& h, const std::vector<Eigen::Vector2i>& points, double radius_cells);

}  // namespace pslam
