#pragma once
// The alignment Gamma of eq. 2 (P-SLAM paper, section III-A): a pair of control points, P1 in the
// target region and P2 in the reference region, and an angle theta taken from the line features
// of the two corners. Gamma rotates by theta about P2, then translates P2 onto P1:
//   x_target = R(theta) (x_reference - P2) + P1.
// Eq. 2 writes this as the 3x3 matrix [R(theta) | P1 - P2] acting on coordinates centred on P2;
// written in map coordinates it is the rigid transform AlignmentTransform() returns.
#include <Eigen/Core>
#include <cmath>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/map_raster.hpp"

namespace pslam {

// Control points in cell coordinates: cell (i, j) has its centre at (i, j), so a point rounds to
// the nearest cell and world = (cell coordinate + 0.5) * resolution.
struct Alignment {
  Eigen::Vector2d target_point{0.0, 0.0};     // P1
  Eigen::Vector2d reference_point{0.0, 0.0};  // P2
  double theta = 0.0;                         // radians, reference direction -> target direction

  Eigen::Vector2d ToTarget(const Eigen::Vector2d& p) const {
    return Eigen::Rotation2Dd(theta) * (p - reference_point) + target_point;
  }
  Eigen::Vector2d ToReference(const Eigen::Vector2d& p) const {
    return Eigen::Rotation2Dd(-theta) * (p - target_point) + reference_point;
  }
};

// Gamma as a rigid transform: AlignmentTransform(p1, p2, theta) * p2 == p1, and it turns every
// direction by theta. Any frame works as long as p1 and p2 are in it (metres for Hypothesis).
inline Pose2D AlignmentTransform(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, double theta) {
  const Eigen::Vector2d t = p1 - Eigen::Rotation2Dd(theta) * p2;
  return {t.x(), t.y(), theta};
}

inline Eigen::Vector2i NearestCell(const Eigen::Vector2d& p) {
  return {static_cast<int>(std::floor(p.x() + 0.5)), static_cast<int>(std::floor(p.y() + 0.5))};
}

// The aligned reference region C~_f' on the cells of 'target_box': each target cell takes the
// state of the map cell nearest to its preimage under Gamma (nearest-neighbour backward warping,
// so every target cell gets exactly one value and no holes appear at oblique angles).
CellRaster AlignReference(const OccupancyGrid& map, const CellBox& target_box, const Alignment& alignment,
                          const CellClassifier& classify);

}  // namespace pslam
