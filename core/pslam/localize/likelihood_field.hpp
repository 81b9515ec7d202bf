#pragma once
// The likelihood-field sensor model over a fixed map, precomputed once: each cell holds the log
// score of an endpoint falling in it (LikelihoodFieldOptions), from an exact distance transform
// of the map's obstacles. The mapping filter scores endpoints by a windowed search instead
// (pslam/matching/scan_likelihood.hpp) because its maps change at every scan; a fixed map pays the
// transform once and then costs one table read per endpoint, which is what thousands of particles
// need.
#include <Eigen/Core>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/localize/mcl_options.hpp"

namespace pslam {

class LikelihoodField {
 public:
  // Throws std::invalid_argument when the map has no obstacle cell: nothing to localize against.
  LikelihoodField(const OccupancyGrid& map, const LikelihoodFieldOptions& options);

  // Sum over the endpoints (robot frame) of their log score at 'pose', before the temperature.
  double LogLikelihood(const std::vector<Eigen::Vector2f>& points, const Pose2D& pose) const;
  // The log score of one endpoint in world coordinates.
  float PointLogLikelihood(const Eigen::Vector2d& world) const;
  // The same, bilinearly interpolated between cell centres: smooth, for refining a pose.
  double InterpolatedLogLikelihood(const Eigen::Vector2d& world) const;
  // The pose within max_shift (m) and max_turn (rad) of 'initial' that maximises the interpolated
  // log-likelihood of the endpoints (robot frame), by a pattern search halving its steps (from
  // 4 cm and 0.02 rad) until they are below min_step (m). The particle cloud limits the filter's
  // estimate to its spread; this does not.
  Pose2D Refine(const std::vector<Eigen::Vector2f>& points, const Pose2D& initial, double max_shift, double max_turn,
                double min_step = 0.002) const;
  // The score of an endpoint max_distance or more from any obstacle, or off the map.
  float miss_log_likelihood() const { return miss_; }
  int occupied_cells() const { return occupied_cells_; }

 private:
  double resolution_;
  CellBox box_;                 // cells covered by the table: the known map plus max_distance
  std::vector<float> table_;    // row-major over box_
  float miss_ = 0.0f;
  int occupied_cells_ = 0;
};

}  // namespace pslam
