#pragma once
// A session engine's running statistics, as plain data (live view, REST, checkpoints).
#include <cstddef>
#include <cstdint>
#include <string>

namespace pslam::server {

// Localize mode: how sure Monte Carlo localization is of the pose (its heaviest particle cluster).
struct LocalizationStats {
  bool localized = false;        // the cluster holds most of the weight and is tight (MclOptions)
  double cluster_weight = 0.0;   // share of the weight in the heaviest cluster
  double position_std_m = 0.0;   // its spread along its widest direction
  double heading_std_rad = 0.0;
  int clusters = 0;
  long long injected = 0;        // random particles injected so far (recovery after kidnapping)
  // Global localization (no start pose): "searching" the map for the robot's place, "look_alike"
  // while another place explains the last metres as well; empty once tracking.
  std::string place;
};

struct EngineStats {
  std::int64_t processed_seq = 0;
  std::int64_t scans = 0;
  std::int64_t updates = 0;
  std::int64_t resamplings = 0;
  int particles = 0;
  double neff = 0.0;
  double scan_rate_hz = 0.0;       // scans processed per second over the last few seconds
  double latency_ms_mean = 0.0;    // input received -> processed by the filter, recent mean
  double latency_ms_max = 0.0;     // recent maximum
  double step_ms_mean = 0.0;       // filter time per scan, recent mean
  std::size_t queued = 0;          // inputs waiting for the filter
  bool rebuilding = false;         // re-running stored inputs after a restart
  // Whether the filter looks lost (pslam/filter/divergence_monitor.hpp): "ok", "degraded" or
  // "lost", and why when not ok.
  std::string tracking = "ok";
  std::string tracking_reason;
  // P-SLAM
  std::int64_t targets = 0;             // exploration targets set (each asks for a prediction)
  std::int64_t predictions_made = 0;    // predictions finished, with or without a hypothesis
  std::int64_t hypotheses = 0;          // predictions that became hypotheses (Psi above threshold)
  double prediction_ms_mean = 0.0;
  double prediction_ms_max = 0.0;
  std::int64_t updates_using_predictions = 0;  // filter updates whose weights used hypotheses
  // Exploration (sessions with a robot to drive; engine/slam_pipeline.hpp, ExplorationStatus):
  // empty state before the first plan and for replays.
  std::string exploration;
  std::string exploration_reason;
  double mapped_m2 = 0.0;
  double predicted_m2 = 0.0;
  int predicted_frontiers = 0;
  // "map", "localize", or the phase of an extend session: "extend_localize" (localizing on the
  // site's map) then "extend_map" (mapping on from it); localization only while localizing.
  std::string mode = "map";
  LocalizationStats localization;
};

}  // namespace pslam::server
