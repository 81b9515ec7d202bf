#include "engine/fixed_map_localization.hpp"

#include <Eigen/Core>

namespace pslam::server {

FixedMapLocalization::FixedMapLocalization(std::shared_ptr<const OccupancyGrid> map, const MclOptions& options,
                                           const std::optional<InitialPose>& initial)
    : map_(std::move(map)), mcl_(*map_, options) {
  if (initial) SetPose(*initial);
}

void FixedMapLocalization::SetPose(const InitialPose& p) {
  const Eigen::Vector3d variance(p.std_xy * p.std_xy, p.std_xy * p.std_xy, p.std_theta * p.std_theta);
  mcl_.SetPose(Pose2D(p.x, p.y, p.theta), variance.asDiagonal().toDenseMatrix());
}

RbpfStep FixedMapLocalization::Add(const LaserScan& scan) {
  const MclUpdate u = mcl_.AddScan(scan);
  handover_.Ready(u);
  RbpfStep step;
  step.updated = u.updated;
  step.resampled = u.resampled;
  step.neff = u.effective_sample_size;
  step.pose = u.estimate;
  trajectory_.push_back(u.estimate);
  const MclStats& s = mcl_.stats();
  stats_.scans = s.scans;
  stats_.updates = s.updates;
  stats_.resamplings = s.resamplings;
  if (u.updated) stats_.neff = u.effective_sample_size;
  return step;
}

LocalizationStats FixedMapLocalization::status() const {
  const MclUpdate& u = mcl_.last();
  LocalizationStats s;
  s.localized = u.localized;
  s.cluster_weight = u.cluster.weight;
  s.position_std_m = u.cluster.position_std;
  s.heading_std_rad = u.cluster.heading_std;
  s.clusters = u.clusters;
  s.injected = mcl_.stats().injected;
  if (u.searching) s.place = u.place.outcome == PlaceMatch::Outcome::kAmbiguous ? "look_alike" : "searching";
  return s;
}

}  // namespace pslam::server
