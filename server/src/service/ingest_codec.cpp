#include "service/ingest_codec.hpp"

#include <bit>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "service/json_fields.hpp"

namespace pslam::server {
namespace {

static_assert(std::endian::native == std::endian::little, "PSC1 is little-endian; add byte swapping here");
constexpr std::size_t kBinaryHeader = 48;
constexpr char kBinaryMagic[4] = {'P', 'S', 'C', '1'};

IngestError Bad(const std::string& message) { return {"bad_message", message}; }

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// Odometry and scan poses: finite numbers.
void ReadPose(JsonFields& f, InputRecord& in) {
  in.x = f.RequiredNumber("x");
  in.y = f.RequiredNumber("y");
  in.theta = f.RequiredNumber("theta");
}

// Bounds of what a robot can report (schema/ws/ingest.md, "Physical bounds"); "" when within them.
std::string OutOfBounds(const InputRecord& in) {
  if (std::abs(in.t) > kMaxStampSeconds) return "t = " + Number(in.t) + " s is not a plausible time stamp";
  if (std::abs(in.x) > kMaxOdometryMeters || std::abs(in.y) > kMaxOdometryMeters ||
      std::abs(in.theta) > kMaxOdometryMeters) {
    return "odometry (" + Number(in.x) + ", " + Number(in.y) + ", " + Number(in.theta) + ") is beyond " +
           Number(kMaxOdometryMeters) + " m (or rad) of the origin";
  }
  if (std::abs(in.v) > kMaxSpeedMetersPerSecond || std::abs(in.w) > 1e3) {
    return "velocities v = " + Number(in.v) + ", w = " + Number(in.w) + " are not plausible";
  }
  for (float r : in.ranges) {
    if (r > kMaxRangeMeters) return "a range of " + Number(r) + " m is beyond " + Number(kMaxRangeMeters) + " m";
  }
  return "";
}

IngestMessage Checked(InputRecord in) {
  const std::string problem = OutOfBounds(in);
  if (problem.empty()) return in;
  return Bad(std::string(in.kind == InputKind::kScan ? "scan " : "odom ") + std::to_string(in.seq) + ": " + problem);
}

IngestMessage DecodeHello(const nlohmann::json& j, const SettingsLimits& limits) {
  JsonFields f(j, "hello");
  f.String("type");
  HelloMessage hello;
  const std::int64_t version = f.RequiredInteger("version");
  if (version != kIngestProtocolVersion) {
    return Bad("hello: protocol version " + std::to_string(version) + " is not supported (this server speaks " +
               std::to_string(kIngestProtocolVersion) + ")");
  }
  hello.robot_id = f.String("robot_id", 128).value_or("");
  hello.session = f.String("session", 64).value_or("new");
  hello.session_name = f.String("session_name", 256).value_or("");
  if (const nlohmann::json* laser = f.Object("laser")) hello.laser = ParseLaserGeometry(*laser, limits, "hello.laser");
  if (const nlohmann::json* settings = f.Object("settings")) hello.settings = *settings;
  hello.redirected = f.Bool("redirected").value_or(false);
  f.RejectUnknown();
  if (hello.session == "new" && !hello.laser) return Bad("hello: laser is required for a new session");
  return hello;
}

std::int64_t ReadSeq(JsonFields& f) {
  const std::int64_t seq = f.RequiredInteger("seq");
  if (seq < 1) f.Fail("seq", "must be at least 1");
  return seq;
}

IngestMessage DecodeOdom(const nlohmann::json& j) {
  JsonFields f(j, "odom");
  f.String("type");
  InputRecord in;
  in.kind = InputKind::kOdometry;
  in.seq = ReadSeq(f);
  in.t = f.RequiredNumber("t");
  ReadPose(f, in);
  in.v = f.NumberOr("v", 0.0);
  in.w = f.NumberOr("w", 0.0);
  f.RejectUnknown();
  return Checked(std::move(in));
}

IngestMessage DecodeScan(const nlohmann::json& j, const LaserGeometry& laser) {
  JsonFields f(j, "scan");
  f.String("type");
  InputRecord in;
  in.kind = InputKind::kScan;
  in.seq = ReadSeq(f);
  in.t = f.RequiredNumber("t");
  const nlohmann::json* odom = f.Object("odom");
  if (!odom) f.Fail("odom", "is required");
  JsonFields o(*odom, "scan.odom");
  ReadPose(o, in);
  o.RejectUnknown();
  const nlohmann::json* ranges = f.Array("ranges");
  if (!ranges) f.Fail("ranges", "is required");
  f.RejectUnknown();
  if (ranges->size() != static_cast<std::size_t>(laser.beams)) {
    return Bad("scan " + std::to_string(in.seq) + ": " + std::to_string(ranges->size()) + " ranges, the laser has " +
               std::to_string(laser.beams) + " beams");
  }
  in.ranges.reserve(ranges->size());
  for (const nlohmann::json& r : *ranges) {
    if (r.is_null()) {
      in.ranges.push_back(std::numeric_limits<float>::quiet_NaN());
      continue;
    }
    if (!r.is_number()) return Bad("scan " + std::to_string(in.seq) + ": ranges must be numbers or null");
    const double v = r.get<double>();
    if (!std::isfinite(v) || v < 0.0) {
      return Bad("scan " + std::to_string(in.seq) + ": ranges must be finite and not negative (null: no return)");
    }
    in.ranges.push_back(static_cast<float>(std::min(v, 1e30)));  // past float's range: still refused below
  }
  return Checked(std::move(in));
}

template <typename T>
T Read(std::span<const std::uint8_t> bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

}  // namespace

IngestMessage DecodeTextMessage(std::string_view text, const LaserGeometry* laser, const SettingsLimits& limits) {
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return Bad("malformed JSON");
  if (!j.is_object()) return Bad("a message must be a JSON object");
  const auto type = j.find("type");
  if (type == j.end() || !type->is_string()) return Bad("a message needs a string 'type'");
  const std::string kind = type->get<std::string>();
  try {
    if (kind == "hello") {
      if (laser) return Bad("hello: already received on this connection");
      return DecodeHello(j, limits);
    }
    if (!laser) return Bad("the first message must be a hello");
    if (kind == "odom") return DecodeOdom(j);
    if (kind == "scan") return DecodeScan(j, *laser);
  } catch (const ApiError& e) {
    return Bad(e.what());
  }
  return Bad("unknown message type '" + kind.substr(0, 32) + "'");
}

IngestMessage DecodeBinaryScan(std::span<const std::uint8_t> bytes, const LaserGeometry* laser) {
  if (!laser) return Bad("the first message must be a hello");
  if (bytes.size() < kBinaryHeader || std::memcmp(bytes.data(), kBinaryMagic, 4) != 0) {
    return Bad("binary scan: not a PSC1 frame (magic or header missing)");
  }
  const auto n = Read<std::uint32_t>(bytes, 44);
  if (bytes.size() != kBinaryHeader + 4ull * n) {
    return Bad("binary scan: " + std::to_string(bytes.size()) + " bytes, the header announces " + std::to_string(n) +
               " ranges (" + std::to_string(kBinaryHeader + 4ull * n) + " bytes)");
  }
  InputRecord in;
  in.kind = InputKind::kScan;
  const auto seq = Read<std::uint64_t>(bytes, 4);
  if (seq < 1 || seq > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    return Bad("binary scan: seq must be at least 1");
  }
  in.seq = static_cast<std::int64_t>(seq);
  in.t = Read<double>(bytes, 12);
  in.x = Read<double>(bytes, 20);
  in.y = Read<double>(bytes, 28);
  in.theta = Read<double>(bytes, 36);
  const std::string what = "scan " + std::to_string(in.seq) + ": ";
  if (!std::isfinite(in.t) || !std::isfinite(in.x) || !std::isfinite(in.y) || !std::isfinite(in.theta)) {
    return Bad(what + "t and odom must be finite");
  }
  if (n != static_cast<std::uint32_t>(laser->beams)) {
    return Bad(what + std::to_string(n) + " ranges, the laser has " + std::to_string(laser->beams) + " beams");
  }
  in.ranges.resize(n);
  std::memcpy(in.ranges.data(), bytes.data() + kBinaryHeader, 4ull * n);
  for (float& r : in.ranges) {
    if (std::isnan(r)) continue;
    if (r < 0.0f) return Bad(what + "ranges must not be negative (NaN: no return)");
    if (std::isinf(r)) r = std::numeric_limits<float>::quiet_NaN();  // +inf: no return
  }
  return Checked(std::move(in));
}

std::string PoseJumpProblem(const InputRecord& previous, const InputRecord& next) {
  const double distance = std::hypot(next.x - previous.x, next.y - previous.y);
  const double dt = std::abs(next.t - previous.t);
  if (distance <= kPoseJumpSlackMeters + kMaxSpeedMetersPerSecond * dt) return "";
  return std::string(next.kind == InputKind::kScan ? "scan " : "odom ") + std::to_string(next.seq) + ": odometry moved " +
         Number(distance) + " m in " + Number(dt) + " s since seq " + std::to_string(previous.seq) + ", faster than " +
         Number(kMaxSpeedMetersPerSecond) + " m/s (wrong units?)";
}

std::string EncodeBinaryScan(const InputRecord& scan) {
  std::string out(kBinaryHeader + 4 * scan.ranges.size(), '\0');
  auto put = [&](std::size_t offset, const auto& value) { std::memcpy(out.data() + offset, &value, sizeof value); };
  std::memcpy(out.data(), kBinaryMagic, 4);
  put(4, static_cast<std::uint64_t>(scan.seq));
  put(12, scan.t);
  put(20, scan.x);
  put(28, scan.y);
  put(36, scan.theta);
  put(44, static_cast<std::uint32_t>(scan.ranges.size()));
  if (!scan.ranges.empty()) std::memcpy(out.data() + kBinaryHeader, scan.ranges.data(), 4 * scan.ranges.size());
  return out;
}

std::string WelcomeMessage(const std::string& session_id, std::int64_t last_acked_seq) {
  return nlohmann::json{{"type", "welcome"}, {"session_id", session_id}, {"last_acked_seq", last_acked_seq}}.dump();
}

std::string RedirectMessage(const std::string& address) {
  return nlohmann::json{{"type", "redirect"}, {"address", address}}.dump();
}

std::string AckMessage(std::int64_t seq) { return nlohmann::json{{"type", "ack"}, {"seq", seq}}.dump(); }

std::string ErrorMessage(const std::string& code, const std::string& message) {
  // Messages may quote input: replace invalid UTF-8 rather than fail to serialise.
  return nlohmann::json{{"type", "error"}, {"code", code}, {"message", message}}.dump(
      -1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string TargetMessage(const ExplorationTarget& t) {
  nlohmann::json path = nlohmann::json::array();
  for (const auto& p : t.path) path.push_back({p[0], p[1]});
  nlohmann::json message{{"type", "target"},
                         {"target", {{"x", t.x}, {"y", t.y}}},
                         {"path", path},
                         {"pose", {{"x", t.pose_x}, {"y", t.pose_y}, {"theta", t.pose_theta}}}};
  if (t.turn > 0.0) message["turn"] = t.turn;
  return message.dump();
}

}  // namespace pslam::server
