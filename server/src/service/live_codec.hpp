#pragma once
// The live view's messages (schema/ws/live.md): JSON text messages for state, and binary frames
// for what is sent every tick and is mostly numbers: map tiles (a 24-byte header and a zlib
// payload), the laser scan and the particles. LiveState is one session's picture as
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
inline constexpr std::size_t kScanFrameHeader = 40;
inline constexpr std::uint8_t kScanEncodingCentimetres = 1;  // u16 per beam, 65535 no return
inline constexpr std::uint16_t kScanNoReturn = 65535;
inline constexpr std::size_t kParticleFrameHeader = 8;

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
// The scan with the sensor's pose in the map frame ('robot' * the scan's sensor offset).
Bytes EncodeScanFrame(std::int64_t seq, const LaserScan& scan, const Pose2D& robot);
Bytes EncodeParticleFrame(std::span<const Pose2D> poses, std::span<const double> weights);
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

  // A mirror of a session another node runs (docs/fleet.md) is kept from what that node's viewers
  // get. Absorb takes one encoded tick; Replace takes a whole picture (a snapshot message and its
  // tile frames) and returns the delta that brings a viewer of the old picture to the new one.
  // Both throw on malformed JSON and then leave the state as it was.
  void Absorb(const LiveDelta& delta);
  LiveDelta Replace(const std::string& snapshot, const std::vector<Bytes>& tiles);

 private:
  std::string session_id_;
  double resolution_;
  std::int64_t scan_seq_ = 0;  // of the last scan frame: an unchanged scan is not sent again
  std::map<TileKey, Bytes> tiles_;
  std::vector<TrajectoryRow> trajectory_;
  nlohmann::json pose_, particles_, stats_, exploration_;
  Bytes particle_frame_;  // the last particle frame sent: an unchanged cloud is not sent again
  std::map<std::int64_t, nlohmann::json> hypotheses_;
};

// A snapshot of a session that is not running, from what storage holds.
std::vector<LiveMessage> StoredSnapshot(const std::string& session_id, const std::string& status, double resolution,
                                        const std::vector<TileRow>& tiles, const std::vector<TrajectoryRow>& trajectory,
                                        const std::vector<HypothesisRecord>& hypotheses, const nlohmann::json& stats);

}  // namespace pslam::server
