#pragma once
// The live view's messages (schema/ws/live.md): JSON text messages for state, and binary tile
// frames (a 24-byte header and a zlib payload) for the map. LiveState is one session's picture as
// the viewers know it: it turns each engine tick into an encoded delta, once for all viewers, and
// gives a full snapshot to a viewer that joins.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "engine/engine_output.hpp"
#include "model/checkpoint.hpp"
#include "model/hypothesis.hpp"

namespace pslam::server {

inline constexpr std::size_t kTileFrameHeader = 24;
inline constexpr std::uint8_t kTileEncodingPercent = 1;  // u8 per cell: 0..100 % occupied, 255 unknown

using Bytes = std::shared_ptr<const std::string>;
using TileKey = std::pair<int, int>;

struct LiveMessage {
  Bytes data;
  bool binary = false;
};

// What one engine tick changed, encoded. Latest-state fields are null when unchanged.
struct LiveDelta {
  std::vector<std::pair<TileKey, Bytes>> tiles;
  Bytes pose, scan, particles, stats, exploration;
  std::int64_t trajectory_first_index = 0;
  std::shared_ptr<const std::vector<TrajectoryRow>> trajectory;  // null or non-empty
  std::vector<std::pair<std::int64_t, Bytes>> hypotheses;        // latest message per hypothesis
};

Bytes EncodeTileFrame(int tx, int ty, std::uint64_t revision, std::span<const std::uint8_t> zlib_cells);
Bytes TrajectoryMessage(std::int64_t first_index, std::span<const TrajectoryRow> rows);
Bytes SessionStatusMessage(const std::string& session_id, const std::string& status);
inline Bytes MakeBytes(std::string s) { return std::make_shared<const std::string>(std::move(s)); }

class LiveState {
 public:
  LiveState(std::string session_id, double resolution) : session_id_(std::move(session_id)), resolution_(resolution) {}

  LiveDelta Apply(const LiveFrame& frame);
  // The snapshot message followed by every tile frame.
  std::vector<LiveMessage> Snapshot() const;
  // The whole trajectory, for a viewer whose pending increments overflowed.
  Bytes FullTrajectory() const { return TrajectoryMessage(0, trajectory_); }

 private:
  std::string session_id_;
  double resolution_;
  std::map<TileKey, Bytes> tiles_;
  std::vector<TrajectoryRow> trajectory_;
  nlohmann::json pose_, particles_, stats_, exploration_;
  std::map<std::int64_t, nlohmann::json> hypotheses_;
};

// A snapshot of a session that is not running, from what storage holds.
std::vector<LiveMessage> StoredSnapshot(const std::string& session_id, const std::string& status, double resolution,
                                        const std::vector<TileRow>& tiles, const std::vector<TrajectoryRow>& trajectory,
                                        const std::vector<HypothesisRecord>& hypotheses, const nlohmann::json& stats);

}  // namespace pslam::server
