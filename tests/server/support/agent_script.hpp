#pragma once
// A scripted agent for the tests: a robot driving through the synthetic room of
// tests/testing/synthetic_world.hpp, sending its scans (JSON or binary) over the ingest protocol.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "server/support/clients.hpp"
#include "service/ingest_codec.hpp"
#include "testing/synthetic_world.hpp"

namespace pslam::server::testing {

inline nlohmann::json LaserJson() {
  return {{"angle_min", -std::numbers::pi / 2}, {"angle_increment", std::numbers::pi / 180.0}, {"beams", 181},
          {"max_range", 20.0}, {"min_range", 0.0}, {"offset", {{"x", 0.0}, {"y", 0.0}, {"theta", 0.0}}}};
}

inline nlohmann::json Hello(const std::string& session = "new", nlohmann::json settings = {{"particles", 4}, {"seed", 7}}) {
  return {{"type", "hello"}, {"version", 1}, {"robot_id", "test-bot"}, {"session", session},
          {"session_name", "test run"}, {"laser", LaserJson()}, {"settings", settings}};
}

// The robot's true pose at step 'i': along the room's length and back, turning slowly.
inline Pose2D PoseAt(std::int64_t i) {
  const double s = std::fmod(static_cast<double>(i) * 0.08, 12.0);
  const double x = s < 6.0 ? -3.0 + s : 9.0 - s;  // there and back, without jumps
  return Pose2D(x, -1.0 + 0.3 * std::sin(s * 0.5), 0.15 * std::sin(s));
}

// Scan 'seq' of the robot at PoseAt(step) among 'walls' (the room's by default), with its odometry
// read in a frame that is not the map's when 'odom_frame' is given: odometry = odom_frame * true pose.
inline InputRecord ScanInput(std::int64_t seq, std::int64_t step, const std::vector<::pslam::testing::Segment>& walls,
                             const Pose2D& odom_frame = Pose2D()) {
  const Pose2D truth = PoseAt(step);
  const Pose2D odom = odom_frame * truth;
  InputRecord in;
  in.seq = seq;
  in.kind = InputKind::kScan;
  in.t = 1700000000.0 + 0.1 * static_cast<double>(step);
  in.x = odom.x;
  in.y = odom.y;
  in.theta = odom.theta;
  in.ranges = ::pslam::testing::RenderScan(truth, walls, odom).ranges;
  return in;
}

inline InputRecord ScanInput(std::int64_t seq, std::int64_t step) {
  static const auto walls = ::pslam::testing::RoomWalls();
  return ScanInput(seq, step, walls);
}

inline nlohmann::json ScanJson(const InputRecord& in) {
  nlohmann::json ranges = nlohmann::json::array();
  for (float r : in.ranges) ranges.push_back(std::isfinite(r) ? nlohmann::json(r) : nlohmann::json());
  return {{"type", "scan"}, {"seq", in.seq}, {"t", in.t}, {"odom", {{"x", in.x}, {"y", in.y}, {"theta", in.theta}}},
          {"ranges", ranges}};
}

inline nlohmann::json OdomJson(std::int64_t seq, std::int64_t step) {
  const Pose2D p = PoseAt(step);
  return {{"type", "odom"}, {"seq", seq}, {"t", 1700000000.0 + 0.1 * static_cast<double>(step) + 0.05},
          {"x", p.x}, {"y", p.y}, {"theta", p.theta}, {"v", 0.8}, {"w", 0.0}};
}

// Sends scan 'seq' (step = seq) as JSON or, for odd seqs when 'mixed', as binary.
inline bool SendScan(WsClient& ws, std::int64_t seq, bool binary) {
  const InputRecord in = ScanInput(seq, seq);
  return binary ? ws.SendBinary(EncodeBinaryScan(in)) : ws.SendJson(ScanJson(in));
}

// Reads until an ack covering 'seq' arrives; errors are collected in ws.skipped.
inline std::int64_t WaitForAck(WsClient& ws, std::int64_t seq, std::chrono::milliseconds timeout = std::chrono::seconds(20)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::int64_t acked = 0;
  while (acked < seq && std::chrono::steady_clock::now() < deadline) {
    auto ack = ws.ReadType("ack", std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()));
    if (!ack) break;
    acked = std::max(acked, (*ack)["seq"].get<std::int64_t>());
  }
  return acked;
}

}  // namespace pslam::server::testing
