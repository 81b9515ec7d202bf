#pragma once
// What a session engine hands to storage at a checkpoint, as plain data.
#include <cstdint>
#include <string>
#include <vector>

#include "model/engine_stats.hpp"
#include "model/hypothesis.hpp"

namespace pslam::server {

// One map tile as stored: zlib(int16 little-endian log-odds, row-major, 'size' x 'size').
struct TileRow {
  int tx = 0, ty = 0;                 // tile index: its cells are tx*size .. tx*size+size-1
  int size = 0;
  std::int64_t revision = 0;
  std::vector<std::uint8_t> data;
};

struct TrajectoryRow {
  std::int64_t scan_index = 0;
  std::int64_t seq = 0;               // the input (scan) this pose belongs to
  double t = 0.0;
  std::string stamp;
  double x = 0.0, y = 0.0, theta = 0.0;
};

// Everything one engine checkpoint writes, in one transaction.
struct Checkpoint {
  std::string session_id;
  std::int64_t processed_seq = 0;
  std::int64_t scans = 0;
  double resolution = 0.05;
  std::vector<TileRow> tiles;               // changed since the previous checkpoint
  std::vector<TrajectoryRow> trajectory;    // new rows (or, if replace_trajectory, all rows)
  bool replace_trajectory = false;
  std::vector<HypothesisRecord> hypotheses; // added or changed
  EngineStats stats;                        // at the checkpoint
  std::string stats_json = "{}";            // 'stats' as JSON, filled in by the service
};

}  // namespace pslam::server
