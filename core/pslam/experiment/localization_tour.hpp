#pragma once
// Monte Carlo localization of a simulated robot touring a world: the robot drives (on its true
// pose; the driver is not what is measured) along planned paths to random free goals, and every
// scan goes to a localizer on a fixed map. The result is the estimate next to the truth at each
// scan, for the tracking error and the distance global localization needs, and the CPU time the
// localizer spent, optionally next to the mapping filter's on the very same scans.
#include <cstdint>
#include <optional>
#include <vector>

#include <random>

#include "pslam/common/pose2d.hpp"
#include "pslam/explore/planning_grid.hpp"
#include "pslam/filter/rbpf_options.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/localize/mcl_options.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

struct LocalizationTourOptions {
  double distance = 60.0;            // m driven before the tour ends
  double max_time = 1200.0;          // s of simulated time, a guard
  std::uint64_t seed = 1;            // goals, simulator and localizer
  bool global = false;               // start without a pose (global localization)
  // Known start: the localizer gets the true start pose with this spread (standard deviations).
  double initial_position_std = 0.2;  // m
  double initial_heading_std = 0.1;   // rad
  // Kidnapping: after this many metres the robot is carried to kidnap_pose (0: never).
  double kidnap_after = 0.0;
  Pose2D kidnap_pose;
  // Active localization: whenever the localizer starts searching for its place (a global start, a
  // kidnapping), the robot first turns once in place, so the search sees all around it rather
  // than the 180 degrees ahead.
  bool look_around = true;
  double look_around_rate = 0.5;     // rad/s
  bool measure_mapping = false;      // also run the mapping filter over the same scans, for its CPU time
  RbpfOptions mapping;
  SimulatorOptions sim;
  MclOptions mcl;
};

struct LocalizationSample {
  double time = 0.0;
  double distance = 0.0;             // m driven so far
  Pose2D truth;
  Pose2D estimate;
  bool localized = false;
  int particles = 0;
};

struct LocalizationTourResult {
  std::vector<LocalizationSample> samples;  // one per scan
  double distance = 0.0;
  int scans = 0;
  int updates = 0;
  double localizer_cpu_ms_per_scan = 0.0;
  double mapping_cpu_ms_per_scan = 0.0;     // 0 unless measure_mapping
  int min_particles = 0, max_particles = 0;
};

// A path from 'from' to a random traversable cell at least a few metres away; empty when none
// was found in a bounded number of tries. How the simulated tours drive.
std::vector<Eigen::Vector2d> RandomRoute(const PlanningGrid& grid, const Eigen::Vector2d& from, std::mt19937_64& rng);

// Throws std::invalid_argument when 'start' (or the kidnap pose) is not free in 'world'.
LocalizationTourResult RunLocalizationTour(const World& world, const OccupancyGrid& map, const Pose2D& start,
                                           const LocalizationTourOptions& options);

// Mean position and heading errors of the samples driven from 'from_distance' on.
struct TrackingError {
  double mean_position = 0.0;        // m
  double mean_heading = 0.0;         // rad, absolute
  double max_position = 0.0;
  int samples = 0;
};
TrackingError MeasureTracking(const std::vector<LocalizationSample>& samples, double from_distance = 0.0);

// The distance driven, counted from 'from_distance', after which the position error stayed below
// 'threshold' to the end; nullopt when it is not below it at the end.
std::optional<double> ConvergenceDistance(const std::vector<LocalizationSample>& samples, double threshold,
                                          double from_distance = 0.0);

}  // namespace pslam
