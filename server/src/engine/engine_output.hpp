#pragma once
// What a running session engine reports, as plain data; the service turns it into wire messages
// and database rows.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pslam/sensor/laser_scan.hpp"

#include "model/checkpoint.hpp"
#include "model/engine_stats.hpp"
#include "model/hypothesis.hpp"
#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam::server {

struct LiveTile {
  int tx = 0, ty = 0;
  std::uint64_t revision = 0;
  std::shared_ptr<const std::vector<std::uint8_t>> cells;  // EncodeLiveTile
};

// The filter started or stopped looking lost (pslam/filter/divergence_monitor.hpp).
struct TrackingChange {
  std::int64_t scan_index = 0;  // the scan at which it changed
  std::int64_t seq = 0;         // its input's seq
  double t = 0.0;               // its input's time
  std::string state;            // "ok", "degraded" or "lost"
  std::string reason;           // empty when ok
};

// One tick of the live view (10 per second on average): what changed since the previous tick.
struct LiveFrame {
  double resolution = 0.05;
  std::shared_ptr<const OccupancyGrid> map;          // the best particle's map at this tick
  std::vector<LiveTile> tiles;                       // changed tiles
  std::optional<Pose2D> pose;                        // robot pose estimate
  std::shared_ptr<const LaserScan> scan;             // the latest scan, drawn at the pose
  std::int64_t scan_seq = 0;                         // its input's seq
  std::int64_t trajectory_first_index = 0;           // scan index of trajectory[0]
  std::vector<TrajectoryRow> trajectory;             // poses of the scans since the previous tick
  std::vector<Pose2D> particles;
  std::vector<double> weights;
  std::vector<HypothesisRecord> hypotheses_changed;
  std::vector<std::int64_t> hypotheses_removed;
  std::vector<std::array<double, 2>> frontiers;
  std::optional<ExplorationTarget> target;
  EngineStats stats;
  bool send_stats = true;  // viewers get stats at most once per stats period; 'stats' is always current
};

}  // namespace pslam::server
