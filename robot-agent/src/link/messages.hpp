#pragma once
// What the agent sends, as values, and their two encodings: the compact spool record (written once
// when the sample is taken) and the wire form of schema/ws/ingest.md (made when it is sent, with
// the session's sequence number, so that a record can be renumbered for a new session).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "common/laser_description.hpp"
#include "pslam/common/pose2d.hpp"

namespace pslam::agent {

struct OdomMessage {
  double t = 0.0;  // seconds since the epoch
  double x = 0.0, y = 0.0, theta = 0.0;
  double v = 0.0, w = 0.0;  // m/s, rad/s
};

struct ScanMessage {
  double t = 0.0;
  Pose2D odom;                // raw odometry interpolated to t
  std::vector<float> ranges;  // metres; NaN: no return
};

using AgentMessage = std::variant<OdomMessage, ScanMessage>;

// Spool payloads. Decode returns nullopt for a payload that is not one of ours.
std::vector<std::uint8_t> EncodeRecord(const AgentMessage& message);
std::optional<AgentMessage> DecodeRecord(std::span<const std::uint8_t> payload);

struct HelloMessage {
  std::string robot_id;
  std::string session = "new";  // "new" or the id of the session to resume
  std::string session_name;     // omitted when empty
  std::string settings_json;    // a JSON object, omitted when empty
  LaserDescription laser;
  bool redirected = false;      // a fleet node sent us here: a new session is to stay here
};

std::string EncodeHello(const HelloMessage& hello);
std::string EncodeOdomJson(const OdomMessage& odom, std::uint64_t seq);
std::string EncodeScanJson(const ScanMessage& scan, std::uint64_t seq);
// The binary form: "PSC1", u64 seq, f64 t, f64 x, y, theta, u32 n, f32 ranges (48 + 4n bytes).
std::vector<std::uint8_t> EncodeScanBinary(const ScanMessage& scan, std::uint64_t seq);
// Straight from a spool record without decoding it (the hot path of a backlog drain).
std::optional<std::vector<std::uint8_t>> ScanRecordToBinary(std::span<const std::uint8_t> record, std::uint64_t seq);
bool IsScanRecord(std::span<const std::uint8_t> record);

// Server to agent.
struct WelcomeMessage {
  std::string session_id;
  std::uint64_t last_acked_seq = 0;
};
struct AckMessage {
  std::uint64_t seq = 0;
};
struct TargetMessage {
  double target_x = 0.0, target_y = 0.0;
  std::vector<std::pair<double, double>> path;  // map frame
  Pose2D pose;                                  // robot in the map frame when planned
  // Radians to turn in place before following the path: the server asks the robot to look all
  // around while it searches the map for the robot's place.
  double turn = 0.0;
};
struct ErrorMessage {
  std::string code;
  std::string message;
};
// Another node of the fleet runs (or is to run) the session: reconnect to 'address' (HOST:PORT).
struct RedirectMessage {
  std::string address;
};
struct UnknownMessage {
  std::string description;  // why it could not be understood
};
using ServerMessage =
    std::variant<WelcomeMessage, AckMessage, TargetMessage, ErrorMessage, RedirectMessage, UnknownMessage>;

ServerMessage ParseServerMessage(std::string_view text);

}  // namespace pslam::agent
