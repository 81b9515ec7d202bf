#include "link/messages.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <numbers>
#include <nlohmann/json.hpp>

#include "link/json_sequence.hpp"

namespace pslam::agent {
namespace {

static_assert(std::endian::native == std::endian::little,
              "records and the binary scan form are little-endian; add byte swapping for this host");

constexpr std::uint8_t kOdomKind = 'O';
constexpr std::uint8_t kScanKind = 'S';
constexpr std::size_t kScanHeader = 1 + 8 + 24 + 4;  // kind, t, odom, n
constexpr std::size_t kOdomBytes = 1 + 6 * 8;
constexpr char kBinaryMagic[4] = {'P', 'S', 'C', '1'};
// A target's turn in place: two full turns at most (a garbled value must not spin the robot for good).
constexpr double kMaxTurnRadians = 4.0 * std::numbers::pi;

template <typename T>
void Put(std::vector<std::uint8_t>& out, T value) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}
template <typename T>
T Get(const std::uint8_t* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// Shortest round-trip text of a number (what nlohmann would print for a double, but for floats
// it prints 2.31 rather than 2.309999942779541).
template <typename T>
void AppendNumber(std::string& out, T value) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, r.ptr);
}

}  // namespace

std::vector<std::uint8_t> EncodeRecord(const AgentMessage& message) {
  std::vector<std::uint8_t> out;
  if (const auto* o = std::get_if<OdomMessage>(&message)) {
    out.reserve(kOdomBytes);
    out.push_back(kOdomKind);
    for (double d : {o->t, o->x, o->y, o->theta, o->v, o->w}) Put(out, d);
    return out;
  }
  const auto& s = std::get<ScanMessage>(message);
  out.reserve(kScanHeader + 4 * s.ranges.size());
  out.push_back(kScanKind);
  for (double d : {s.t, s.odom.x, s.odom.y, s.odom.theta}) Put(out, d);
  Put(out, static_cast<std::uint32_t>(s.ranges.size()));
  const auto* p = reinterpret_cast<const std::uint8_t*>(s.ranges.data());
  out.insert(out.end(), p, p + 4 * s.ranges.size());
  return out;
}

bool IsScanRecord(std::span<const std::uint8_t> record) {
  return record.size() >= kScanHeader && record[0] == kScanKind &&
         record.size() == kScanHeader + 4ull * Get<std::uint32_t>(record.data() + 33);
}

std::optional<AgentMessage> DecodeRecord(std::span<const std::uint8_t> payload) {
  if (payload.size() == kOdomBytes && payload[0] == kOdomKind) {
    const std::uint8_t* p = payload.data() + 1;
    return OdomMessage{Get<double>(p), Get<double>(p + 8), Get<double>(p + 16),
                       Get<double>(p + 24), Get<double>(p + 32), Get<double>(p + 40)};
  }
  if (!IsScanRecord(payload)) return std::nullopt;
  const std::uint8_t* p = payload.data() + 1;
  ScanMessage s;
  s.t = Get<double>(p);
  s.odom.x = Get<double>(p + 8);
  s.odom.y = Get<double>(p + 16);
  s.odom.theta = Get<double>(p + 24);
  s.ranges.resize(Get<std::uint32_t>(p + 32));
  std::memcpy(s.ranges.data(), p + 36, 4 * s.ranges.size());
  return s;
}

std::string EncodeHello(const HelloMessage& hello) {
  nlohmann::json j = {
      {"type", "hello"},
      {"version", 1},
      {"robot_id", hello.robot_id},
      {"session", hello.session},
      {"laser",
       {{"angle_min", hello.laser.angle_min},
        {"angle_increment", hello.laser.angle_increment},
        {"beams", hello.laser.beams},
        {"max_range", hello.laser.max_range},
        {"min_range", hello.laser.min_range},
        {"offset", {{"x", hello.laser.offset.x}, {"y", hello.laser.offset.y}, {"theta", hello.laser.offset.theta}}}}}};
  if (!hello.session_name.empty()) j["session_name"] = hello.session_name;
  if (!hello.settings_json.empty()) j["settings"] = nlohmann::json::parse(hello.settings_json);
  if (hello.redirected) j["redirected"] = true;
  return j.dump();
}

std::string EncodeOdomJson(const OdomMessage& o, std::uint64_t seq) {
  std::string out = "{\"type\":\"odom\",\"seq\":";
  AppendNumber(out, seq);
  const std::pair<const char*, double> fields[] = {{",\"t\":", o.t}, {",\"x\":", o.x},         {",\"y\":", o.y},
                                                   {",\"theta\":", o.theta}, {",\"v\":", o.v}, {",\"w\":", o.w}};
  for (const auto& [key, value] : fields) {
    out += key;
    AppendNumber(out, std::isfinite(value) ? value : 0.0);
  }
  out += '}';
  return out;
}

std::string EncodeScanJson(const ScanMessage& s, std::uint64_t seq) {
  std::string out;
  out.reserve(96 + 7 * s.ranges.size());
  out = "{\"type\":\"scan\",\"seq\":";
  AppendNumber(out, seq);
  out += ",\"t\":";
  AppendNumber(out, s.t);
  out += ",\"odom\":{\"x\":";
  AppendNumber(out, s.odom.x);
  out += ",\"y\":";
  AppendNumber(out, s.odom.y);
  out += ",\"theta\":";
  AppendNumber(out, s.odom.theta);
  out += "},\"ranges\":[";
  for (std::size_t i = 0; i < s.ranges.size(); ++i) {
    if (i > 0) out += ',';
    if (std::isfinite(s.ranges[i])) {
      AppendNumber(out, s.ranges[i]);
    } else {
      out += "null";  // a beam without a return
    }
  }
  out += "]}";
  return out;
}

std::vector<std::uint8_t> EncodeScanBinary(const ScanMessage& scan, std::uint64_t seq) {
  return *ScanRecordToBinary(EncodeRecord(scan), seq);
}

std::optional<std::vector<std::uint8_t>> ScanRecordToBinary(std::span<const std::uint8_t> record, std::uint64_t seq) {
  if (!IsScanRecord(record)) return std::nullopt;
  std::vector<std::uint8_t> out;
  out.reserve(record.size() + 11);
  out.insert(out.end(), kBinaryMagic, kBinaryMagic + 4);
  Put(out, seq);
  out.insert(out.end(), record.begin() + 1, record.end());  // t, odom, n, ranges: same layout
  return out;
}

ServerMessage ParseServerMessage(std::string_view text) {
  try {
    const auto j = nlohmann::json::parse(text);
    const std::string type = j.at("type").get<std::string>();
    if (type == "ack") return AckMessage{SequenceField(j, "seq")};
    if (type == "welcome") {
      return WelcomeMessage{j.at("session_id").get<std::string>(), SequenceField(j, "last_acked_seq", 0)};
    }
    if (type == "error") return ErrorMessage{j.value("code", std::string()), j.value("message", std::string())};
    if (type == "redirect") return RedirectMessage{j.at("address").get<std::string>()};
    if (type == "target") {
      TargetMessage t;
      t.target_x = j.at("target").at("x").get<double>();
      t.target_y = j.at("target").at("y").get<double>();
      for (const auto& point : j.at("path")) t.path.emplace_back(point.at(0).get<double>(), point.at(1).get<double>());
      if (j.contains("pose")) {
        const auto& p = j.at("pose");
        t.pose = Pose2D(p.at("x").get<double>(), p.at("y").get<double>(), p.at("theta").get<double>());
      }
      t.turn = j.value("turn", 0.0);
      if (!(t.turn >= 0.0 && t.turn <= kMaxTurnRadians)) {
        return UnknownMessage{"target turn must be 0 to " + std::to_string(kMaxTurnRadians) + " rad"};
      }
      return t;
    }
    return UnknownMessage{"unknown message type '" + type + "'"};
  } catch (const std::exception& e) {
    return UnknownMessage{std::string("unreadable server message: ") + e.what()};
  }
}

}  // namespace pslam::agent
