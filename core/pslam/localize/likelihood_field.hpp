#pragma once
// The likelihood-field sensor model over a fixed map, precomputed once: each cell holds the log
// score of an endpoint falling in it (LikelihoodFieldOptions), from an exact distance transform
// of the map's obstacles. The mapping filter scores endpoints by a windowed search instead
// (pslam/matching/scan_likelihood.hpp) because its maps change at every scan; a fixed map pays the
// transform once and then costs one table read per endpoint, which is what thousands of particles
// need. Where the map never observed a cell, obstacles seen later may be added (localizing
// through what the map lacks).
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/localize/mcl_options.hpp"

namespace pslam {

// A Gaussian about the pose a refinement starts from, with the given information (inverse
// covariance): where the scan pins a direction down the pose moves, where it does not (along a
// corridor, past a wall the map lacks) the prior holds it. The default is no prior.
struct RefinePrior {
  Eigen::Matrix2d position_information = Eigen::Matrix2d::Zero();  // 1/m^2
  double heading_information = 0.0;                                 // 1/rad^2
  double likelihood_weight = 1.0;                                   // on the scan's log-likelihood
};

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
  // The same for an endpoint seen from 'sensor': as a miss where the cell a step back toward the
  // sensor is occupied too, since the beam would have stopped there. Inside a wall two or more
  // cells thick the field is flat; this puts the endpoint on the face that was seen.
  double SeenLogLikelihood(const Eigen::Vector2d& world, const Eigen::Vector2d& sensor) const;
  // The pose within max_shift (m) and max_turn (rad) of 'initial' that maximises the interpolated
  // log-likelihood of the endpoints (robot frame), by a pattern search halving its steps (from
  // 4 cm and 0.02 rad) until they are below min_step (m). The particle cloud limits the filter's
  // estimate to its spread; this does not.
  // With a prior, the pose maximises likelihood_weight times that log-likelihood plus the log of
  // a Gaussian about 'initial' (RefinePrior).
  Pose2D Refine(const std::vector<Eigen::Vector2f>& points, const Pose2D& initial, double max_shift, double max_turn,
                double min_step = 0.002, const RefinePrior& prior = RefinePrior()) const;
  // Adds an obstacle seen at 'world' in a cell the map never observed, within the table (the
  // map's known bounds plus max_distance), so that later endpoints there score against what was
  // seen rather than against the nearest wall of the map. Returns whether it was added: not for
  // cells the map observed, cells within fill_clearance of an obstacle already (so walls stay
  // thin, as the first look drew them), or cells off the table. Beyond the map's bounds a lost
  // estimate would draw a world of its own, fit it, and never look lost.
  bool AddUnmappedObstacle(const Eigen::Vector2d& world);
  // Whether an endpoint at 'world' lies within fill_clearance of an obstacle; nullopt where the map
  // never observed its cell.
  std::optional<bool> ExplainedByMap(const Eigen::Vector2d& world) const;
  // Whether a beam from 'sensor' to 'endpoint' passes through an obstacle before its last
  // fill_clearance: the beam cannot have, so the pose it was cast from is wrong.
  bool BeamBlocked(const Eigen::Vector2d& sensor, const Eigen::Vector2d& endpoint) const;
  int added_obstacles() const { return added_obstacles_; }
  // The score of an endpoint max_distance or more from any obstacle, or off the map.
  float miss_log_likelihood() const { return miss_; }
  int occupied_cells() const { return occupied_cells_; }

 private:
  std::size_t Index(int x, int y) const {
    return static_cast<std::size_t>(y - box_.min.y()) * static_cast<std::size_t>(box_.width()) +
           static_cast<std::size_t>(x - box_.min.x());
  }
  // The table's cell holding 'world', or nullopt off the table (or for a non-finite point).
  std::optional<Eigen::Vector2i> TableCell(const Eigen::Vector2d& world) const;
  bool NearObstacle(const Eigen::Vector2i& cell) const;  // an obstacle within fill_clearance

  LikelihoodFieldOptions options_;
  double resolution_;
  CellBox box_;                 // cells covered by the table: the known map plus max_distance
  template <typename T>
  double Interpolate(const std::vector<T>& table, const Eigen::Vector2d& world, double outside) const;

  std::vector<float> table_;    // row-major over box_
  std::vector<std::uint8_t> occupied_;  // 1 for an obstacle cell, same layout
  std::vector<std::uint8_t> known_;     // 1 where the map observed the cell, same layout
  float miss_ = 0.0f;
  int occupied_cells_ = 0;
  int added_obstacles_ = 0;
};

}  // namespace pslam
