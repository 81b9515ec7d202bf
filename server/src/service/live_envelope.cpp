#include "service/live_envelope.hpp"

#include <cstring>

namespace pslam::server {
namespace {

// Parts after the header: a u8 tag, a u32 length, the bytes.
enum Tag : std::uint8_t {
  kTile = 1, kPose, kScan, kParticles, kStats, kExploration, kTrajectory, kHypothesis, kSnapshot, kStatus,
};
constexpr std::size_t kTrajectoryRowBytes = 48;  // scan_index, seq, t, x, y, theta

template <typename T>
void Append(std::string& out, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  out.append(raw, sizeof(T));
}

template <typename T>
T Load(std::string_view bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

void Part(std::string& out, Tag tag, std::string_view bytes) {
  Append<std::uint8_t>(out, tag);
  Append<std::uint32_t>(out, static_cast<std::uint32_t>(bytes.size()));
  out.append(bytes);
}

void PartIf(std::string& out, Tag tag, const Bytes& bytes) {
  if (bytes) Part(out, tag, *bytes);
}

std::string Header(LiveEnvelope::Kind kind, std::uint64_t node, std::uint64_t seq, std::int64_t published_us) {
  std::string out("PSLR", 4);
  Append<std::uint8_t>(out, 1);  // version
  Append<std::uint8_t>(out, static_cast<std::uint8_t>(kind));
  Append<std::uint16_t>(out, 0);
  Append(out, node);
  Append(out, seq);
  Append(out, published_us);
  return out;
}

bool HasMagic(std::string_view frame, const char* magic, std::size_t header) {
  return frame.size() >= header && frame.compare(0, 4, magic) == 0;
}

}  // namespace

std::string EncodeDeltaEnvelope(std::uint64_t node, std::uint64_t seq, std::int64_t published_us, const LiveDelta& d) {
  std::string out = Header(LiveEnvelope::Kind::kDelta, node, seq, published_us);
  for (const auto& [key, frame] : d.tiles) Part(out, kTile, *frame);
  PartIf(out, kPose, d.pose);
  PartIf(out, kScan, d.scan);
  PartIf(out, kParticles, d.particles);
  PartIf(out, kStats, d.stats);
  PartIf(out, kExploration, d.exploration);
  if (d.trajectory) {
    std::string rows;
    Append(rows, d.trajectory_first_index);
    for (const TrajectoryRow& r : *d.trajectory) {
      Append(rows, r.scan_index);
      Append(rows, r.seq);
      Append(rows, r.t);
      Append(rows, r.x);
      Append(rows, r.y);
      Append(rows, r.theta);
    }
    Part(out, kTrajectory, rows);
  }
  for (const auto& [id, message] : d.hypotheses) {
    std::string part;
    Append(part, id);
    part += *message;
    Part(out, kHypothesis, part);
  }
  return out;
}

std::string EncodeKeyframeEnvelope(std::uint64_t node, std::uint64_t seq, std::int64_t published_us,
                                   const std::vector<LiveMessage>& snapshot) {
  std::string out = Header(LiveEnvelope::Kind::kKeyframe, node, seq, published_us);
  for (const LiveMessage& m : snapshot) Part(out, m.binary ? kTile : kSnapshot, *m.data);
  return out;
}

std::string EncodeEndEnvelope(std::uint64_t node, std::uint64_t seq, std::int64_t published_us, const std::string& status) {
  std::string out = Header(LiveEnvelope::Kind::kEnd, node, seq, published_us);
  Part(out, kStatus, status);
  return out;
}

Result<LiveEnvelope> DecodeLiveEnvelope(std::string_view bytes) {
  if (bytes.size() > kMaxLiveEnvelope) return Error{"envelope of " + std::to_string(bytes.size()) + " bytes is too large"};
  if (bytes.size() < kLiveEnvelopeHeader || bytes.compare(0, 4, "PSLR") != 0) return Error{"not a live envelope"};
  if (bytes[4] != 1) return Error{"unknown envelope version " + std::to_string(static_cast<int>(bytes[4]))};
  LiveEnvelope e;
  const auto kind = static_cast<std::uint8_t>(bytes[5]);
  if (kind < 1 || kind > 3) return Error{"unknown envelope kind " + std::to_string(kind)};
  e.kind = static_cast<LiveEnvelope::Kind>(kind);
  e.node = Load<std::uint64_t>(bytes, 8);
  e.seq = Load<std::uint64_t>(bytes, 16);
  e.published_us = Load<std::int64_t>(bytes, 24);
  bool has_snapshot = false, has_status = false;
  for (std::size_t at = kLiveEnvelopeHeader; at < bytes.size();) {
    if (bytes.size() - at < 5) return Error{"truncated part header"};
    const auto tag = static_cast<std::uint8_t>(bytes[at]);
    const auto length = Load<std::uint32_t>(bytes, at + 1);
    at += 5;
    if (length > bytes.size() - at) return Error{"part longer than the envelope"};
    const std::string_view part = bytes.substr(at, length);
    at += length;
    const bool delta = e.kind == LiveEnvelope::Kind::kDelta;
    switch (tag) {
      case kTile: {
        if (!HasMagic(part, "PSTL", kTileFrameHeader)) return Error{"bad tile frame"};
        if (e.kind == LiveEnvelope::Kind::kEnd) return Error{"tile in an end envelope"};
        Bytes frame = MakeBytes(std::string(part));
        if (delta) {
          e.delta.tiles.emplace_back(TileKey{Load<std::int32_t>(part, 4), Load<std::int32_t>(part, 8)}, std::move(frame));
        } else {
          e.tiles.push_back(std::move(frame));
        }
        break;
      }
      case kPose:
      case kStats:
      case kExploration: {
        if (!delta) return Error{"state message outside a delta"};
        Bytes& slot = tag == kPose ? e.delta.pose : tag == kStats ? e.delta.stats : e.delta.exploration;
        slot = MakeBytes(std::string(part));
        break;
      }
      case kScan:
        if (!delta || !HasMagic(part, "PSSC", kScanFrameHeader)) return Error{"bad scan frame"};
        e.delta.scan = MakeBytes(std::string(part));
        break;
      case kParticles:
        if (!delta || !HasMagic(part, "PSPT", kParticleFrameHeader) ||
            part.size() != kParticleFrameHeader + 16 * std::size_t{Load<std::uint32_t>(part, 4)}) {
          return Error{"bad particle frame"};
        }
        e.delta.particles = MakeBytes(std::string(part));
        break;
      case kTrajectory: {
        if (!delta || part.size() < 8 || (part.size() - 8) % kTrajectoryRowBytes != 0 || part.size() == 8) {
          return Error{"bad trajectory"};
        }
        e.delta.trajectory_first_index = Load<std::int64_t>(part, 0);
        auto rows = std::make_shared<std::vector<TrajectoryRow>>((part.size() - 8) / kTrajectoryRowBytes);
        for (std::size_t i = 0; i < rows->size(); ++i) {
          const std::size_t r = 8 + i * kTrajectoryRowBytes;
          TrajectoryRow& row = (*rows)[i];
          row.scan_index = Load<std::int64_t>(part, r);
          row.seq = Load<std::int64_t>(part, r + 8);
          row.t = Load<double>(part, r + 16);
          row.x = Load<double>(part, r + 24);
          row.y = Load<double>(part, r + 32);
          row.theta = Load<double>(part, r + 40);
        }
        e.delta.trajectory = std::move(rows);
        break;
      }
      case kHypothesis:
        if (!delta || part.size() <= 8) return Error{"bad hypothesis event"};
        e.delta.hypotheses.emplace_back(Load<std::int64_t>(part, 0), MakeBytes(std::string(part.substr(8))));
        break;
      case kSnapshot:
        if (e.kind != LiveEnvelope::Kind::kKeyframe || has_snapshot) return Error{"unexpected snapshot"};
        e.snapshot = std::string(part);
        has_snapshot = true;
        break;
      case kStatus:
        if (e.kind != LiveEnvelope::Kind::kEnd || has_status) return Error{"unexpected status"};
        e.status = std::string(part);
        has_status = true;
        break;
      default:
        return Error{"unknown part " + std::to_string(tag)};
    }
  }
  if (e.kind == LiveEnvelope::Kind::kKeyframe && !has_snapshot) return Error{"keyframe without a snapshot"};
  if (e.kind == LiveEnvelope::Kind::kEnd && !has_status) return Error{"end without a status"};
  return e;
}

}  // namespace pslam::server
