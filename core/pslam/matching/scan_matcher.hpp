#pragma once
// Gauss-Newton scan-to-map matching (as in Kohlbrecher et al.'s Hector mapping): minimise
// sum_i (1 - M(T(p_i)))^2 over the pose T, where M is the smooth occupancy evidence of the map.
// It runs coarse to fine over max-pooled levels of the same grid.
#include <Eigen/Core>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

struct ScanMatchOptions {
  int coarsest_level = 1;            // levels coarsest_level ... 0; each doubles the cell size
  // When the first match converged, a second one starts from this level and replaces it if it
  // scores at least second_start_margin times as high. From coarse cells a match reaches far but
  // now and then settles on a wrong optimum; from finer ones it reaches less far and settles
  // better. -1: one match only.
  int second_start_level = -1;
  double second_start_margin = 1.05;
  int iterations_per_level = 10;
  double max_translation_step = 0.1; // metres per iteration, a guard against wild steps
  double max_rotation_step = 0.1;    // radians per iteration
  double damping = 1e-3;             // Levenberg term relative to the Hessian's diagonal
  // Degeneracy (Zhang, Kaess and Singh, ICRA 2016): where the scan constrains one horizontal
  // direction far less than the other (a corridor seen without its ends), the cost is flat along
  // it and the solver slides on noise. Steps along a translation direction whose eigenvalue of
  // J^T J is below this share of the other one are dropped, so that odometry holds that direction.
  // 0: off.
  double degenerate_ratio = 0.0;
  // A prior pulling the pose toward the initial guess (as Cartographer's Ceres scan matcher
  // weighs translation and rotation against occupied space): per endpoint, a shift d and a turn a
  // cost (prior_translation_weight * d)^2 + (prior_rotation_weight * a)^2 on top of (1 - M)^2.
  // Where the scan's cost is flat (a corridor, or a map of a few scans whose cells carry little
  // evidence yet) the guess holds instead of the slide that the coarse levels' pooling starts.
  // The weight sets how far the map may pull: at 30 a match moves a centimetre or two. 0: off.
  double prior_translation_weight = 0.0;  // per metre
  double prior_rotation_weight = 0.0;     // per radian
  // On the finest level, read each cell's evidence where its hits landed rather than at the cell's
  // centre (OccupancyField): a wall on a cell's edge otherwise pulls endpoints half a cell into
  // itself, and a scan seeing more of one side's walls turns by that much.
  bool hit_offsets = false;
  double min_score = 0.15;           // below this mean evidence the match is not trusted
  // A match that moves the pose further than this from the initial guess has most likely locked
  // onto the wrong structure (a parallel wall, the next door): it is not trusted either.
  double max_correction_translation = 0.5;  // metres
  double max_correction_rotation = 0.35;    // radians
};

struct ScanMatchResult {
  Pose2D pose;
  double score = 0.0;           // mean evidence at the endpoints, in [0, 1]
  bool converged = false;       // score reached min_score
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();  // J^T J at the optimum, on the finest level
};

ScanMatchResult MatchScan(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points_in_robot,
                          const Pose2D& initial, const ScanMatchOptions& options);

// How well a match pins the position down: the weaker translation direction's eigenvalue of
// J^T J (ScanMatchResult::hessian) as a share of the stronger one's; 0 in a featureless corridor,
// 1 where the scan constrains both directions alike.
double TranslationConstraintRatio(const Eigen::Matrix3d& hessian);

// Mean evidence of the points at a pose (finest level).
double ScoreScan(const OccupancyGrid& grid, const std::vector<Eigen::Vector2f>& points_in_robot, const Pose2D& pose);

}  // namespace pslam
