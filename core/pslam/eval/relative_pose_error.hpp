#pragma once
// The relation-based metric of Kümmerle et al. 2009, "On measuring the accuracy of SLAM
// algorithms": for every ground-truth relation (the motion between two scans), compare it with the
// same motion taken from the estimated trajectory. Unlike an absolute error it does not reward or
// punish one early mistake over and over along the rest of the trajectory.
#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/eval/trajectory_io.hpp"

namespace pslam {

// Pose at 'stamp2' in the frame of the pose at 'stamp1': Between(X_stamp1, X_stamp2).
struct Relation {
  std::string stamp1, stamp2;
  Pose2D delta;
};

// Reads a relations file, lines "t1 t2 x y z roll pitch yaw"; z, roll and pitch are ignored (the
// Freiburg 2D benchmark sets them to 0). Throws std::runtime_error with "file:line: ..." on bad lines.
std::vector<Relation> ReadRelations(const std::string& path);
std::vector<Relation> ReadRelations(std::istream& in, const std::string& name);

// Logs write stamps with microseconds, relation files sometimes with fewer decimals. Scans can be
// closer than this (1479 pairs in the Intel log are), so a stamp takes the nearest pose, not the first
// one within reach.
constexpr double kDefaultStampTolerance = 1e-3;  // s

// Statistics over the used relations; std is the population standard deviation (divide by n).
// All statistics are 0 when no relation was used.
struct RpeResult {
  std::size_t used = 0;
  std::size_t missing = 0;  // relations with a stamp that no trajectory stamp is within the tolerance of
  double stamp_tolerance_s = kDefaultStampTolerance;  // the tolerance the stamps were matched with
  double max_stamp_offset_s = 0.0;  // largest |relation stamp - matched trajectory stamp| of the used relations
  double trans_mean = 0.0, trans_std = 0.0;        // m
  double rot_mean_deg = 0.0, rot_std_deg = 0.0;    // deg
  double trans2_mean = 0.0, trans2_std = 0.0;      // m^2
  double rot2_mean_deg2 = 0.0, rot2_std_deg2 = 0.0;  // deg^2
  double trans_max = 0.0;                          // m
  double rot_max_deg = 0.0;                        // deg
};

// Per relation: error = Between(delta, Between(est_t1, est_t2)); translational error is the norm of
// its translation, rotational error |theta| in degrees. Stamps match by time, not text: each
// relation stamp takes the trajectory pose with the nearest stamp, if that is at most
// 'stamp_tolerance_s' away (so "976052905.16730" finds "976052905.167303"). A trajectory stamp's
// time is its text when that is a number, else StampedPose::time. If the trajectory repeats a
// stamp, its first pose is used.
RpeResult ComputeRpe(const std::vector<StampedPose>& trajectory, const std::vector<Relation>& relations,
                     double stamp_tolerance_s = kDefaultStampTolerance);

// A message when more than 'max_missing_percent' % of the relations (or all of them) found no
// pose: an error over the few that matched would look valid but measure little. nullopt if fine.
std::optional<std::string> TooManyMissing(const RpeResult& result, double max_missing_percent);

}  // namespace pslam
