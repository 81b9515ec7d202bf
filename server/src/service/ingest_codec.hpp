#pragma once
// Decoding of the agent protocol (schema/ws/ingest.md): hello, odom, scan (JSON or the binary PSC1
// form) and the server's replies. A message that cannot be accepted decodes to an IngestError with
// the protocol's error code and a message that says what is wrong.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "model/hypothesis.hpp"
#include "model/input.hpp"
#include "model/session_settings.hpp"
#include "service/settings_codec.hpp"

namespace pslam::server {

inline constexpr int kIngestProtocolVersion = 1;

// Physical bounds of an input: beyond them it is refused (bad_message) and not stored, since a
// filter fed such a pose would try to map the space between (schema/ws/ingest.md).
inline constexpr double kMaxOdometryMeters = 1e7;        // |x|, |y| (and |theta| in rad)
inline constexpr double kMaxStampSeconds = 1e11;         // |t|
inline constexpr double kMaxRangeMeters = 1e4;
inline constexpr double kMaxSpeedMetersPerSecond = 50.0;  // odometry between consecutive inputs ...
inline constexpr double kPoseJumpSlackMeters = 1.0;       // ... plus this, for equal time stamps

struct HelloMessage {
  int version = kIngestProtocolVersion;
  std::string robot_id;
  std::string session = "new";     // "new" or the id of a session to resume
  std::string session_name;
  std::optional<LaserGeometry> laser;
  nlohmann::json settings;         // null when absent; parsed against the server defaults later
  bool redirected = false;         // a fleet node sent the agent here: a new session stays here
};

struct IngestError {
  std::string code;                // bad_message | unauthorized | too_large | unknown_session | overloaded
  std::string message;
};

using IngestMessage = std::variant<HelloMessage, InputRecord, IngestError>;

// A text frame. Before the hello ('laser' null) only a hello is accepted; after it, odom and scan,
// whose ranges must number laser->beams.
IngestMessage DecodeTextMessage(std::string_view text, const LaserGeometry* laser, const SettingsLimits& limits);
// A binary frame: a PSC1 scan.
IngestMessage DecodeBinaryScan(std::span<const std::uint8_t> bytes, const LaserGeometry* laser);
// Why 'next' cannot follow 'previous' (the session's last admitted input): its odometry moved
// faster than kMaxSpeedMetersPerSecond over the time between them. Empty when it can.
std::string PoseJumpProblem(const InputRecord& previous, const InputRecord& next);
// Encodes a PSC1 scan (for agents and tests).
std::string EncodeBinaryScan(const InputRecord& scan);

std::string WelcomeMessage(const std::string& session_id, std::int64_t last_acked_seq);
std::string AckMessage(std::int64_t seq);
std::string ErrorMessage(const std::string& code, const std::string& message);
// Another node of the fleet runs (or is to run) the session: the agent reconnects to 'address'.
std::string RedirectMessage(const std::string& address);
std::string TargetMessage(const ExplorationTarget& target);

}  // namespace pslam::server
