#pragma once
// Localize mode's filter: Monte Carlo localization (pslam/localize) on a site's fixed map, and what
// the engine reports of it in the shapes it reports the mapping filter's (RbpfStep, RbpfStats).
#include <memory>
#include <optional>
#include <vector>

#include "model/engine_stats.hpp"
#include "model/session_settings.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/localize/mapping_handover.hpp"
#include "pslam/localize/monte_carlo_localizer.hpp"

namespace pslam::server {

class FixedMapLocalization {
 public:
  // Starts at 'initial' if given, else globally at the first scan. Throws std::invalid_argument for
  // bad options or a map without free cells or obstacles.
  FixedMapLocalization(std::shared_ptr<const OccupancyGrid> map, const MclOptions& options,
                       const std::optional<InitialPose>& initial);

  // Re-localizes from a pose (an operator's, or the agent's): the particles are drawn around it.
  void SetPose(const InitialPose& pose);
  // Forgets the pose: the particles spread over the whole map again (global localization).
  void StartGlobal() { mcl_.StartGlobal(); }
  // The pose estimate at 'scan' (its odometry carries it between filter updates).
  RbpfStep Add(const LaserScan& scan);

  const OccupancyGrid& map() const { return *map_; }
  const std::shared_ptr<const OccupancyGrid>& shared_map() const { return map_; }
  const std::vector<Pose2D>& particles() const { return mcl_.particles(); }
  std::vector<double> weights() const { return mcl_.weights(); }
  const std::vector<Pose2D>& trajectory() const { return trajectory_; }
  const RbpfStats& stats() const { return stats_; }
  LocalizationStats status() const;
  // Extend mode: the pose is good enough to start mapping from (MappingHandover).
  bool ready_to_map() const { return handover_.ready(); }

 private:
  std::shared_ptr<const OccupancyGrid> map_;
  MonteCarloLocalizer mcl_;
  MappingHandover handover_;
  std::vector<Pose2D> trajectory_;
  RbpfStats stats_;
};

}  // namespace pslam::server
