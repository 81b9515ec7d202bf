#pragma once
// Pure encode/decode of the Pioneer P2OS/AROS/ARCOS serial protocol (shared/protocols/p2os-arcos.md):
// packet framing and checksum (§2-3), command arguments (§5), the standard SIP (§7), odometry with
// position wrap-around (§8) and the P3-DX conversion factors (§9). No I/O here: the client and the
// test's robot simulator both build on these functions.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "devices/frame_buffer.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam::agent::p2os {

inline constexpr std::uint8_t kHeader0 = 0xFA;
inline constexpr std::uint8_t kHeader1 = 0xFB;
inline constexpr std::uint8_t kArgInt = 0x3B;     // positive integer, 2 bytes LE
inline constexpr std::uint8_t kArgNegInt = 0x1B;  // negative integer, 2 bytes LE magnitude
inline constexpr std::uint8_t kArgString = 0x2B;
// Both sides keep packets at or below 200 bytes (§2 CONFLICT); we still *accept* the largest byte
// count the manual allows so that a long SIP from newer firmware is not thrown away.
inline constexpr std::size_t kMaxByteCount = 249;

// Command numbers (§6). PULSE and SYNC0 share 0; OPEN and SYNC1 share 1; CLOSE and SYNC2 share 2.
enum Command : std::uint8_t {
  kPulse = 0,
  kSync0 = 0,
  kSync1 = 1,
  kSync2 = 2,
  kOpen = 1,
  kClose = 2,
  kEnable = 4,
  kSetOdometry = 7,
  kVel = 11,
  kConfig = 18,
  kRotVel = 21,
  kSonar = 28,
  kStop = 29,
  kHostBaud = 50,
};

// Server packet types (§7, §10).
inline constexpr std::uint8_t kSipStopped = 0x32;
inline constexpr std::uint8_t kSipMoving = 0x33;
inline bool IsStandardSip(std::uint8_t type) { return type == kSipStopped || type == kSipMoving; }

// §3: 16-bit sum of big-endian byte pairs; an odd last byte is XORed into the low byte.
std::uint16_t Checksum(std::span<const std::uint8_t> payload);

// A whole packet: FA FB, byte count, payload, checksum (high byte first).
std::vector<std::uint8_t> EncodePacket(std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> EncodeCommand(std::uint8_t command);
// Signed integer argument: ARGINT with the value, or ARGNINT with its magnitude (§5). The value is
// clamped to the 16-bit magnitude the protocol can carry.
std::vector<std::uint8_t> EncodeCommand(std::uint8_t command, int value);

// A client command as the robot sees it (used by the robot simulator).
struct DecodedCommand {
  std::uint8_t command = 0;
  std::optional<int> argument;  // absent for argument-less commands and string arguments
};
std::optional<DecodedCommand> DecodeCommand(std::span<const std::uint8_t> payload);

// Conversion factors selected by the SYNC2 subclass (§9).
struct RobotParams {
  double angle_conv_rad = 0.001534;  // per THPOS unit (2*pi/4096)
  double dist_conv_mm = 1.0;         // per XPOS/YPOS unit
  double vel_conv_mm_s = 1.0;        // per wheel-velocity unit
  double diff_conv = 0.0056;         // (R-L)/2 wheel velocity to rad/s, when ROTVEL is absent
};
// "p3dx-sh" (ARCOS) and "p3dx" (older controller); anything else gets ARIA's built-in defaults.
RobotParams ParamsForSubclass(const std::string& subclass);

// The SYNC2 reply: three NUL-terminated strings after the 0x02 type byte.
struct RobotIdentity {
  std::string name, robot_class, subclass;
};
std::optional<RobotIdentity> ParseSync2Reply(std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> EncodeSync2Reply(const RobotIdentity& identity);  // payload only

struct SonarReading {
  std::uint8_t number = 0;
  std::uint16_t range = 0;
};

// The standard SIP, raw units (§7). Optional trailing fields are present only if the firmware
// sent them.
struct Sip {
  std::uint8_t type = kSipStopped;
  std::uint16_t x_pos = 0;  // only the low 15 bits are meaningful (§8)
  std::uint16_t y_pos = 0;
  std::int16_t th_pos = 0;  // 4096 units per revolution
  std::int16_t left_vel = 0;
  std::int16_t right_vel = 0;
  std::uint8_t battery_decivolts = 0;
  std::uint16_t stall_bump = 0;
  std::int16_t control = 0;
  std::uint16_t flags = 0;  // bit 0: motors enabled
  std::uint8_t compass = 0;
  std::vector<SonarReading> sonar;
  std::uint8_t grip_state = 0, anport = 0, analog = 0, digin = 0, digout = 0;
  std::optional<std::uint16_t> battery_x10;
  std::optional<std::int8_t> charge_state;
  std::optional<std::int16_t> rot_vel_decideg_s;  // 0.1 deg/s
  std::optional<std::uint16_t> fault_flags;

  bool motors_enabled() const { return (flags & 0x1) != 0; }
};
// nullopt if the payload is not a standard SIP or is too short for its sonar block.
std::optional<Sip> DecodeSip(std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> EncodeSipPayload(const Sip& sip);

// Turns successive SIPs into an unbounded odometry pose (§8): XPOS/YPOS deltas on 15 bits with
// wrap-around, absolute heading from THPOS, velocities from the wheel speeds or ROTVEL.
class OdometryIntegrator {
 public:
  explicit OdometryIntegrator(RobotParams params) : params_(params) {}
  OdometryReading Update(const Sip& sip, double timestamp);

 private:
  RobotParams params_;
  bool started_ = false;
  std::uint16_t last_x_ = 0, last_y_ = 0;
  double x_units_ = 0.0, y_units_ = 0.0;  // unwrapped position in encoder units
};

struct Packet {
  std::vector<std::uint8_t> payload;  // type/command byte first, checksum excluded
  double time = 0.0;                  // arrival time of the packet's first byte
};

struct ParserStats {
  std::size_t packets = 0;
  std::size_t bad_checksum = 0;   // framed packets whose checksum failed: dropped
  std::size_t bad_length = 0;     // impossible byte counts: dropped
  std::size_t skipped_bytes = 0;  // bytes discarded while hunting for FA FB
};

// Incremental receiver with resynchronisation (§2): hunt for FA FB, read the count, verify the
// checksum; on failure drop one byte and hunt again, so a valid packet hidden inside a corrupt one
// is still found.
class PacketParser {
 public:
  // 'byte_seconds': see FrameBuffer::Push.
  void Push(std::span<const std::uint8_t> bytes, double arrival_time, double byte_seconds = 0.0) {
    buffer_.Push(bytes, arrival_time, byte_seconds);
  }
  std::optional<Packet> Next();
  // Forgets a partial packet (ARIA gives up after 100 ms without a byte).
  void DiscardPartial();
  bool has_partial() const { return buffer_.size() > 0; }
  const ParserStats& stats() const { return stats_; }

 private:
  FrameBuffer buffer_;
  ParserStats stats_;
};

}  // namespace pslam::agent::p2os
