#pragma once
// Extend mode on a simulated robot: a map from an earlier session, a world that has changed since,
// and a tour through it. The robot first localizes on the old map (Monte Carlo, from its start
// with some spread), and once MappingHandover allows it the mapping filter takes over, every
// particle's map starting as the old map (RbpfOptions::prior_map) at the localized pose, the first
// scan matched to it. The robot drives (on its true pose; the driver is not what is measured) to
// the given places first, then along planned paths to random goals. The result is the new map, to
// be scored against the changed world.
#include <cstdint>
#include <memory>
#include <vector>

#include "pslam/filter/rbpf_options.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/localize/mapping_handover.hpp"
#include "pslam/localize/mcl_options.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

struct ExtendTourOptions {
  double distance = 120.0;           // m driven before the tour ends
  double max_time = 3000.0;          // s of simulated time, a guard
  std::uint64_t seed = 1;            // goals, simulator, localizer and filter
  double initial_position_std = 0.2;  // m: the localizer's start spread around the true start
  double initial_heading_std = 0.1;   // rad
  std::vector<Eigen::Vector2d> visit_first;  // goals driven to before the random ones
  RbpfOptions mapping;               // prior_map and initial_pose are set by the tour
  SimulatorOptions sim;
  MclOptions mcl;
  MappingHandoverOptions handover;
};

struct ExtendTourResult {
  OccupancyGrid map;                 // the best particle's map at the end (the new version)
  bool localized = false;            // mapping took over
  int localize_scans = 0;            // scans the localizer took before it did (MappingHandover)
  int scans = 0;
  double distance = 0.0;             // m driven
  double final_position_error = 0.0; // m, of the mapping filter's pose at the last scan
};

// Throws std::invalid_argument when 'start' is not free in 'world'.
ExtendTourResult RunExtendTour(const World& world, std::shared_ptr<const OccupancyGrid> old_map, const Pose2D& start,
                               const ExtendTourOptions& options);

}  // namespace pslam
