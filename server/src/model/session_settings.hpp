#pragma once
// What a session is made of besides its inputs: the laser's geometry (from the agent's hello) and
// the mapping settings (server defaults, overridden per session by hello or by a replay request).
#include <cstdint>
#include <optional>
#include <string>

namespace pslam::server {

struct LaserGeometry {
  double angle_min = 0.0;          // radians
  double angle_increment = 0.0;    // radians
  int beams = 0;
  double max_range = 0.0;          // metres
  double min_range = 0.0;          // metres
  double offset_x = 0.0, offset_y = 0.0, offset_theta = 0.0;  // sensor pose in the robot frame
};

// Where a localizing robot starts: a Gaussian around (x, y, theta) on the site's map.
struct InitialPose {
  double x = 0.0, y = 0.0, theta = 0.0;  // metres, radians
  double std_xy = 0.3;                    // m
  double std_theta = 0.2;                 // rad
};

struct SessionSettings {
  int particles = 30;
  std::uint64_t seed = 1;
  bool predict = true;             // run the structure predictor (P-SLAM) when the engine has one
  int threads = 1;                 // worker threads of this session's filter
  double resolution = 0.05;        // metres per cell
  double linear_update = 0.25;     // metres of motion between filter updates
  double angular_update = 0.2;     // radians of turn between filter updates
  double resample_threshold = 0.5; // resample when N_eff < threshold * particles
  // Scan matching's degeneracy guard (ScanMatchOptions::degenerate_ratio), 0: off. Along a corridor
  // whose ends the laser does not see, the match keeps odometry instead of sliding (the core's
  // default, RbpfOptions).
  double degenerate_ratio = 0.15;
  // Scan matching's prior toward odometry (ScanMatchOptions::prior_translation_weight), 0: off.
  // Worth it only for wheels far better than the scan's flattest direction: the simulated robot's
  // (30, as its explorations use); real logs' odometry lost accuracy with it.
  double odometry_prior = 0.0;
  // Scan matching reads each cell's evidence where its hits landed (ScanMatchOptions::hit_offsets),
  // as the core does by default. The simulated worlds' walls lie on cell edges, where matching on
  // cell centres holds the map on the true grid: their explorations turn this off.
  bool hit_offsets = true;
  // The session fails ("memory limit") rather than let its maps grow past this; the engine's own
  // accounting (particle grids, shared tiles once) plus what the map's extent costs to plan on.
  int memory_limit_mb = 1024;
  // Settings of the structure predictor as a JSON object, kept opaque here: the predictor layer
  // parses (and validates) it, so adding a predictor tunable does not touch the server.
  std::string predictor_json = "{}";
  // "map" builds a map from nothing; "localize" runs Monte Carlo localization on a fixed map of
  // 'site' (version 'map_version') and maps nothing; "extend" localizes on it the same way, then
  // maps on from it, and its final map becomes the site's next version when the session closes.
  std::string mode = "map";
  std::string site;                // the site the session belongs to; empty: none
  std::int64_t map_version = 0;    // localize, extend: the site's map version (0 in a request: its latest)
  std::optional<InitialPose> initial_pose;  // localize, extend: none means global localization
  // Localization options as a JSON object of pslam/localize/mcl_options.hpp names, parsed (and
  // validated) by the engine like the predictor's.
  std::string localization_json = "{}";
  // Not stored: derived from the session's source. Sessions with a robot get exploration targets
  // planned on the map; replays have no robot to drive, and infer targets from the heading.
  bool plan_targets = false;
};

}  // namespace pslam::server
