#include "devices/p2os_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pslam/common/pose2d.hpp"

namespace pslam::agent::p2os {
namespace {

constexpr std::size_t kSipFixedBytes = 20;  // type .. sonar count, before the sonar block

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::size_t remaining() const { return bytes_.size() - pos_; }
  std::uint8_t U8() { return bytes_[pos_++]; }
  std::uint16_t U16() {
    const std::uint16_t v = static_cast<std::uint16_t>(bytes_[pos_] | (bytes_[pos_ + 1] << 8));
    pos_ += 2;
    return v;
  }
  std::int16_t S16() { return static_cast<std::int16_t>(U16()); }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
};

void PutU16(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v & 0xFF));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
}

// Per-SIP change of a 15-bit wrapping counter (§8, ARIA's method).
int WrappedDelta(std::uint16_t now, std::uint16_t before) {
  int d = static_cast<int>(now & 0x7FFF) - static_cast<int>(before & 0x7FFF);
  if (d > 0x1000) d -= 0x8000;
  if (d < -0x1000) d += 0x8000;
  return d;
}

}  // namespace

std::uint16_t Checksum(std::span<const std::uint8_t> payload) {
  std::uint16_t c = 0;
  std::size_t i = 0;
  for (; i + 1 < payload.size(); i += 2) {
    c = static_cast<std::uint16_t>(c + ((payload[i] << 8) | payload[i + 1]));
  }
  if (i < payload.size()) c ^= payload[i];
  return c;
}

std::vector<std::uint8_t> EncodePacket(std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out;
  out.reserve(payload.size() + 5);
  out.push_back(kHeader0);
  out.push_back(kHeader1);
  out.push_back(static_cast<std::uint8_t>(payload.size() + 2));
  out.insert(out.end(), payload.begin(), payload.end());
  const std::uint16_t c = Checksum(payload);
  out.push_back(static_cast<std::uint8_t>(c >> 8));
  out.push_back(static_cast<std::uint8_t>(c & 0xFF));
  return out;
}

std::vector<std::uint8_t> EncodeCommand(std::uint8_t command) {
  const std::uint8_t payload[] = {command};
  return EncodePacket(payload);
}

std::vector<std::uint8_t> EncodeCommand(std::uint8_t command, int value) {
  const int magnitude = std::min(std::abs(value), 0x7FFF);
  const std::uint8_t payload[] = {command, value < 0 ? kArgNegInt : kArgInt,
                                  static_cast<std::uint8_t>(magnitude & 0xFF),
                                  static_cast<std::uint8_t>(magnitude >> 8)};
  return EncodePacket(payload);
}

std::optional<DecodedCommand> DecodeCommand(std::span<const std::uint8_t> payload) {
  if (payload.empty()) return std::nullopt;
  DecodedCommand c;
  c.command = payload[0];
  if (payload.size() >= 4 && (payload[1] == kArgInt || payload[1] == kArgNegInt)) {
    const int raw = payload[2] | (payload[3] << 8);
    c.argument = payload[1] == kArgNegInt ? -raw : raw;
  }
  return c;
}

RobotParams ParamsForSubclass(const std::string& subclass) {
  std::string lower = subclass;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  RobotParams p;  // ARIA's built-in defaults equal the p3dx-sh values
  if (lower == "p3dx") p.dist_conv_mm = 0.485;
  return p;
}

std::optional<RobotIdentity> ParseSync2Reply(std::span<const std::uint8_t> payload) {
  if (payload.empty() || payload[0] != kSync2) return std::nullopt;
  std::vector<std::string> fields(1);
  for (std::size_t i = 1; i < payload.size(); ++i) {
    if (payload[i] == 0) {
      fields.emplace_back();
    } else {
      fields.back().push_back(static_cast<char>(payload[i]));
    }
  }
  if (fields.size() < 4) return std::nullopt;  // three terminated strings leave a 4th empty field
  return RobotIdentity{fields[0], fields[1], fields[2]};
}

std::vector<std::uint8_t> EncodeSync2Reply(const RobotIdentity& identity) {
  std::vector<std::uint8_t> payload{kSync2};
  for (const std::string* s : {&identity.name, &identity.robot_class, &identity.subclass}) {
    payload.insert(payload.end(), s->begin(), s->end());
    payload.push_back(0);
  }
  return payload;
}

std::optional<Sip> DecodeSip(std::span<const std::uint8_t> payload) {
  if (payload.size() < kSipFixedBytes || !IsStandardSip(payload[0])) return std::nullopt;
  Reader r(payload);
  Sip s;
  s.type = r.U8();
  s.x_pos = r.U16();
  s.y_pos = r.U16();
  s.th_pos = r.S16();
  s.left_vel = r.S16();
  s.right_vel = r.S16();
  s.battery_decivolts = r.U8();
  s.stall_bump = r.U16();
  s.control = r.S16();
  s.flags = r.U16();
  s.compass = r.U8();
  const std::size_t sonar_count = r.U8();
  if (r.remaining() < 3 * sonar_count) return std::nullopt;
  for (std::size_t i = 0; i < sonar_count; ++i) {
    SonarReading sr;
    sr.number = r.U8();
    sr.range = r.U16();
    s.sonar.push_back(sr);
  }
  // Trailing fields: parse each only while bytes remain (firmware versions append, §7).
  if (r.remaining() >= 5) {
    s.grip_state = r.U8();
    s.anport = r.U8();
    s.analog = r.U8();
    s.digin = r.U8();
    s.digout = r.U8();
  } else {
    return s;
  }
  if (r.remaining() >= 2) s.battery_x10 = r.U16();
  if (r.remaining() >= 1) s.charge_state = static_cast<std::int8_t>(r.U8());
  if (r.remaining() >= 2) s.rot_vel_decideg_s = r.S16();
  if (r.remaining() >= 2) s.fault_flags = r.U16();
  return s;
}

std::vector<std::uint8_t> EncodeSipPayload(const Sip& s) {
  std::vector<std::uint8_t> out;
  out.push_back(s.type);
  PutU16(out, s.x_pos);
  PutU16(out, s.y_pos);
  PutU16(out, static_cast<std::uint16_t>(s.th_pos));
  PutU16(out, static_cast<std::uint16_t>(s.left_vel));
  PutU16(out, static_cast<std::uint16_t>(s.right_vel));
  out.push_back(s.battery_decivolts);
  PutU16(out, s.stall_bump);
  PutU16(out, static_cast<std::uint16_t>(s.control));
  PutU16(out, s.flags);
  out.push_back(s.compass);
  out.push_back(static_cast<std::uint8_t>(s.sonar.size()));
  for (const auto& sr : s.sonar) {
    out.push_back(sr.number);
    PutU16(out, sr.range);
  }
  for (std::uint8_t b : {s.grip_state, s.anport, s.analog, s.digin, s.digout}) out.push_back(b);
  // Optional fields are cumulative: each one is only meaningful if all before it are present.
  if (!s.battery_x10) return out;
  PutU16(out, *s.battery_x10);
  if (!s.charge_state) return out;
  out.push_back(static_cast<std::uint8_t>(*s.charge_state));
  if (!s.rot_vel_decideg_s) return out;
  PutU16(out, static_cast<std::uint16_t>(*s.rot_vel_decideg_s));
  if (!s.fault_flags) return out;
  PutU16(out, *s.fault_flags);
  return out;
}

OdometryReading OdometryIntegrator::Update(const Sip& sip, double timestamp) {
  if (!started_) {
    // The first SIP after OPEN is the reference; keep the robot's own origin so that x, y and
    // THPOS stay in one consistent frame.
    started_ = true;
    x_units_ = static_cast<double>(sip.x_pos & 0x7FFF);
    y_units_ = static_cast<double>(sip.y_pos & 0x7FFF);
  } else {
    x_units_ += WrappedDelta(sip.x_pos, last_x_);
    y_units_ += WrappedDelta(sip.y_pos, last_y_);
  }
  last_x_ = sip.x_pos;
  last_y_ = sip.y_pos;

  OdometryReading r;
  r.timestamp = timestamp;
  r.pose = Pose2D(x_units_ * params_.dist_conv_mm / 1000.0, y_units_ * params_.dist_conv_mm / 1000.0,
                  sip.th_pos * params_.angle_conv_rad);
  const double left = sip.left_vel * params_.vel_conv_mm_s;
  const double right = sip.right_vel * params_.vel_conv_mm_s;
  r.translational_velocity = (left + right) / 2.0 / 1000.0;
  r.rotational_velocity = sip.rot_vel_decideg_s
                              ? *sip.rot_vel_decideg_s / 10.0 * std::numbers::pi / 180.0
                              : (right - left) / 2.0 * params_.diff_conv;
  return r;
}

std::optional<Packet> PacketParser::Next() {
  while (buffer_.size() >= 3) {
    if (buffer_[0] != kHeader0 || buffer_[1] != kHeader1) {
      buffer_.Consume(1);
      ++stats_.skipped_bytes;
      continue;
    }
    const std::size_t count = buffer_[2];
    if (count < 3 || count > kMaxByteCount) {  // needs at least one payload byte + checksum
      buffer_.Consume(1);
      ++stats_.bad_length;
      continue;
    }
    if (buffer_.size() < count + 3) return std::nullopt;  // partial: wait for more bytes
    const auto payload = buffer_.View(3, count - 2);
    const std::uint16_t sent = static_cast<std::uint16_t>((buffer_[count + 1] << 8) | buffer_[count + 2]);
    if (Checksum(payload) != sent) {
      buffer_.Consume(1);  // not 'count + 3': a real header may sit inside the bad packet
      ++stats_.bad_checksum;
      continue;
    }
    Packet p{{payload.begin(), payload.end()}, 0.0};
    p.time = buffer_.TakeFrame(count + 3);
    ++stats_.packets;
    return p;
  }
  return std::nullopt;
}

void PacketParser::DiscardPartial() {
  stats_.skipped_bytes += buffer_.size();
  buffer_.Consume(buffer_.size());
}

}  // namespace pslam::agent::p2os
