#pragma once
// What the P-SLAM structure predictor produces, as plain data: the server stores, filters and
// streams these without knowing how they were made.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pslam::server {

struct GridCell {
  int x = 0, y = 0;
};

struct PredictedCell {
  int x = 0, y = 0;
  float occupancy = 0.5f;  // predicted probability of occupancy
};

// One predicted structure: a known region (around 'reference_cell') registered onto the unexplored
// region around 'target_cell' by a rotation 'theta' and a translation.
// A stored map of a site: which one a hypothesis took its reference from.
struct SiteMapRef {
  std::string site;
  std::int64_t version = 0;
};

struct HypothesisRecord {
  std::int64_t id = 0;              // unique within the session
  double time = 0.0;                // Unix seconds of the prediction (or of the last status change)
  GridCell target_cell;
  GridCell reference_cell;          // in the reference's map: the session's own, or reference_map
  std::optional<SiteMapRef> reference_map;  // none: the session's own map
  double theta = 0.0;               // radians
  double translation_x = 0.0, translation_y = 0.0;  // metres
  double psi = 0.0;                 // registration score of the prediction
  double area = 0.0;                // square metres covered by 'cells'
  std::vector<PredictedCell> cells;
  std::string status = "pending";   // pending | confirmed | refuted | expired
  double hit_ratio = 0.0;           // eq. 23: share of endpoints in the hypothesis that a predicted wall explains
  double psi_observed = 0.0;        // Psi of the prediction against what was observed later
};

// The next exploration goal, in the map frame, with the path to it and the robot pose it was
// planned from (the agent tracks the path in its odometry frame through that correspondence).
struct ExplorationTarget {
  double x = 0.0, y = 0.0;
  std::vector<std::array<double, 2>> path;
  double pose_x = 0.0, pose_y = 0.0, pose_theta = 0.0;
  double turn = 0.0;  // radians to turn in place before the path: looking around (localize mode)
};

}  // namespace pslam::server
