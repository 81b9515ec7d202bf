#pragma once
// What a node publishes to Redis for one session's live stream (docs/fleet.md): a binary
// envelope around the very messages its own viewers get. A delta carries one tick's encoded
// messages, a keyframe the whole picture (the snapshot message and every tile frame), an end the
// session's final status. The header says who published (a node's random id), in what order (a
// per-session sequence number, so a receiver sees a gap) and when (for latency figures).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"
#include "service/live_codec.hpp"

namespace pslam::server {

inline constexpr std::size_t kLiveEnvelopeHeader = 32;
// Larger payloads are refused on both sides: a keyframe of a very large map, or garbage.
inline constexpr std::size_t kMaxLiveEnvelope = 32u << 20;

struct LiveEnvelope {
  enum class Kind : std::uint8_t { kDelta = 1, kKeyframe = 2, kEnd = 3 };
  Kind kind = Kind::kDelta;
  std::uint64_t node = 0;
  std::uint64_t seq = 0;
  std::int64_t published_us = 0;  // system clock, microseconds since the Unix epoch
  LiveDelta delta;                // kDelta
  std::string snapshot;           // kKeyframe: the snapshot message (JSON)
  std::vector<Bytes> tiles;       // kKeyframe: its tile frames
  std::string status;             // kEnd
};

std::string EncodeDeltaEnvelope(std::uint64_t node, std::uint64_t seq, std::int64_t published_us, const LiveDelta& delta);
// 'snapshot' as LiveState::Snapshot returns it: the snapshot message, then tile frames.
std::string EncodeKeyframeEnvelope(std::uint64_t node, std::uint64_t seq, std::int64_t published_us,
                                   const std::vector<LiveMessage>& snapshot);
std::string EncodeEndEnvelope(std::uint64_t node, std::uint64_t seq, std::int64_t published_us, const std::string& status);
// Checks every length and magic; anything malformed is an error, never a partial envelope.
Result<LiveEnvelope> DecodeLiveEnvelope(std::string_view bytes);

}  // namespace pslam::server
