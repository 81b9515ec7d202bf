#include "link/messages.hpp"

#include "agent_options.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>

namespace pslam::agent {
namespace {

ScanMessage MakeScan() {
  ScanMessage s;
  s.t = 1700000000.130;
  s.odom = Pose2D(1.2, -0.4, 0.31);
  s.ranges = {2.31f, 2.29f, std::numeric_limits<float>::quiet_NaN(), 7.9f};
  return s;
}

TEST(MessagesTest, RecordsRoundTrip) {
  const ScanMessage scan = MakeScan();
  const auto decoded = DecodeRecord(EncodeRecord(scan));
  ASSERT_TRUE(decoded);
  const auto& s = std::get<ScanMessage>(*decoded);
  EXPECT_EQ(s.t, scan.t);
  EXPECT_EQ(s.odom.theta, scan.odom.theta);
  ASSERT_EQ(s.ranges.size(), 4u);
  EXPECT_TRUE(std::isnan(s.ranges[2]));
  const OdomMessage odom{1.5, 1, 2, 3, 0.2, -0.1};
  const auto o = std::get<OdomMessage>(*DecodeRecord(EncodeRecord(odom)));
  EXPECT_EQ(o.w, -0.1);
  EXPECT_FALSE(DecodeRecord(std::vector<std::uint8_t>{'S', 1, 2}));
}

TEST(MessagesTest, BinaryScanLayoutIsTheSchemaOne) {
  const auto bytes = EncodeScanBinary(MakeScan(), 18);
  ASSERT_EQ(bytes.size(), 48u + 4 * 4);
  EXPECT_EQ(std::memcmp(bytes.data(), "PSC1", 4), 0);
  std::uint64_t seq;
  double t, x, theta;
  std::uint32_t n;
  float r0, r2;
  std::memcpy(&seq, bytes.data() + 4, 8);
  std::memcpy(&t, bytes.data() + 12, 8);
  std::memcpy(&x, bytes.data() + 20, 8);
  std::memcpy(&theta, bytes.data() + 36, 8);
  std::memcpy(&n, bytes.data() + 44, 4);
  std::memcpy(&r0, bytes.data() + 48, 4);
  std::memcpy(&r2, bytes.data() + 56, 4);
  EXPECT_EQ(seq, 18u);
  EXPECT_EQ(t, 1700000000.130);
  EXPECT_EQ(x, 1.2);
  EXPECT_DOUBLE_EQ(theta, 0.31);
  EXPECT_EQ(n, 4u);
  EXPECT_EQ(r0, 2.31f);
  EXPECT_TRUE(std::isnan(r2));
}

TEST(MessagesTest, JsonFormsMatchTheSchemaExamples) {
  const auto scan = nlohmann::json::parse(EncodeScanJson(MakeScan(), 18));
  EXPECT_EQ(scan["type"], "scan");
  EXPECT_EQ(scan["seq"], 18);
  EXPECT_DOUBLE_EQ(scan["t"].get<double>(), 1700000000.130);
  EXPECT_DOUBLE_EQ(scan["odom"]["y"].get<double>(), -0.4);
  EXPECT_EQ(scan["ranges"].dump(), "[2.31,2.29,null,7.9]");  // shortest float text, null for no return
  const auto odom = nlohmann::json::parse(EncodeOdomJson({1700000000.125, 1.2, -0.4, 0.31, 0.2, 0.0}, 17));
  EXPECT_EQ(odom, nlohmann::json::parse(
                      R"({"type": "odom", "seq": 17, "t": 1700000000.125, "x": 1.2, "y": -0.4, "theta": 0.31, "v": 0.2, "w": 0.0})"));
  HelloMessage hello;
  hello.robot_id = "pioneer-1";
  hello.laser = {-1.5707963, 0.0174533, 181, 8.0, 0.0, Pose2D(0.16, 0, 0)};
  const auto h = nlohmann::json::parse(EncodeHello(hello));
  EXPECT_EQ(h["type"], "hello");
  EXPECT_EQ(h["version"], 1);
  EXPECT_EQ(h["session"], "new");
  EXPECT_EQ(h["laser"]["beams"], 181);
  EXPECT_DOUBLE_EQ(h["laser"]["offset"]["x"].get<double>(), 0.16);
  EXPECT_FALSE(h.contains("session_name"));
}

TEST(MessagesTest, SettingsFromTheCommandLineGoIntoTheHello) {
  const ParsedOptions parsed = ParseAgentOptions({"--server", "127.0.0.1:9", "--source", "sim:maze", "--settings", R"({"degenerate_ratio": 0.15, "particles": 40})"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  HelloMessage hello;
  hello.settings_json = parsed.options->session_settings_json;
  const auto h = nlohmann::json::parse(EncodeHello(hello));
  EXPECT_DOUBLE_EQ(h["settings"]["degenerate_ratio"].get<double>(), 0.15);
  EXPECT_EQ(h["settings"]["particles"], 40);
  EXPECT_FALSE(nlohmann::json::parse(EncodeHello(HelloMessage{})).contains("settings"));
  // Not a JSON object: refused at once, naming the option.
  for (const char* bad : {"[1, 2]", "{\"particles\": ", "40"}) {
    const ParsedOptions refused = ParseAgentOptions({"--server", "127.0.0.1:9", "--source", "sim:maze", "--settings", bad});
    EXPECT_FALSE(refused.options) << bad;
    EXPECT_NE(refused.error.find("--settings"), std::string::npos) << refused.error;
  }
}

TEST(MessagesTest, LocalizeOptionsGoIntoTheHelloSettings) {
  const std::vector<std::string> base = {"--server", "127.0.0.1:9", "--source", "sim:maze"};
  const auto parse = [&](std::vector<std::string> extra) {
    extra.insert(extra.begin(), base.begin(), base.end());
    return ParseAgentOptions(extra);
  };
  const ParsedOptions parsed = parse({"--settings", R"({"particles": 40, "mode": "map"})", "--mode", "localize", "--site",
                                      "site-0123456789abcdef", "--initial-pose", "1.5,-2,0.25"});
  ASSERT_TRUE(parsed.options) << parsed.error;
  HelloMessage hello;
  hello.settings_json = parsed.options->session_settings_json;
  const auto settings = nlohmann::json::parse(EncodeHello(hello))["settings"];
  EXPECT_EQ(settings["mode"], "localize");  // the flag over the same key of --settings
  EXPECT_EQ(settings["site"], "site-0123456789abcdef");
  EXPECT_EQ(settings["particles"], 40);
  EXPECT_EQ(settings["initial_pose"], (nlohmann::json{{"x", 1.5}, {"y", -2.0}, {"theta", 0.25}}));
  EXPECT_TRUE(parse({}).options->session_settings_json.empty());  // no settings: none sent

  // Refused at once, each naming what is wrong.
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--mode", "walk"}, "--mode"},
      {{"--mode", "localize"}, "--site"},
      {{"--mode", "extend"}, "--site"},
      {{"--initial-pose", "1,2,0.5", "--site", "site-0123456789abcdef"}, "--initial-pose is for --mode localize"},
      {{"--mode", "localize", "--site", "site-0123456789abcdef", "--initial-pose", "1,2"}, "--initial-pose"},
      {{"--mode", "localize", "--site", "site-0123456789abcdef", "--initial-pose", "1,x,2"}, "--initial-pose"},
  };
  for (const auto& [extra, message] : refused) {
    const ParsedOptions r = parse(extra);
    EXPECT_FALSE(r.options) << message;
    EXPECT_NE(r.error.find(message), std::string::npos) << r.error;
  }
}

TEST(MessagesTest, ParsesServerMessages) {
  const auto w = std::get<WelcomeMessage>(ParseServerMessage(R"({"type": "welcome", "session_id": "s-1", "last_acked_seq": 7})"));
  EXPECT_EQ(w.session_id, "s-1");
  EXPECT_EQ(w.last_acked_seq, 7u);
  EXPECT_EQ(std::get<AckMessage>(ParseServerMessage(R"({"type": "ack", "seq": 18})")).seq, 18u);
  const auto t = std::get<TargetMessage>(ParseServerMessage(
      R"({"type": "target", "target": {"x": 4.5, "y": 2.0}, "path": [[0.0, 0.0], [2.0, 1.0], [4.5, 2.0]], "pose": {"x": 0.0, "y": 0.0, "theta": 0.0}})"));
  ASSERT_EQ(t.path.size(), 3u);
  EXPECT_EQ(t.path[1].first, 2.0);
  EXPECT_EQ(t.turn, 0.0);
  const auto look = std::get<TargetMessage>(ParseServerMessage(
      R"({"type": "target", "target": {"x": 0, "y": 0}, "path": [], "pose": {"x": 0, "y": 0, "theta": 0}, "turn": 6.28})"));
  EXPECT_EQ(look.turn, 6.28);
  for (const char* turn : {"-1", "1e9", "\"round\""}) {
    const std::string text = std::string(R"({"type": "target", "target": {"x": 0, "y": 0}, "path": [], "turn": )") + turn + "}";
    EXPECT_TRUE(std::holds_alternative<UnknownMessage>(ParseServerMessage(text))) << text;
  }
  // Sequence numbers that are not non-negative integers (a fuzzed welcome carried -7.7e128).
  for (const char* seq : {"-1", "2.5", "-7.66e128", "1e300", "\"7\""}) {
    EXPECT_TRUE(std::holds_alternative<UnknownMessage>(
        ParseServerMessage(std::string(R"({"type": "welcome", "session_id": "s-1", "last_acked_seq": )") + seq + "}")))
        << seq;
    EXPECT_TRUE(std::holds_alternative<UnknownMessage>(ParseServerMessage(std::string(R"({"type": "ack", "seq": )") + seq + "}")))
        << seq;
  }
  EXPECT_EQ(std::get<WelcomeMessage>(ParseServerMessage(R"({"type": "welcome", "session_id": "s-1"})")).last_acked_seq, 0u);
  const auto e = std::get<ErrorMessage>(ParseServerMessage(R"({"type": "error", "code": "overloaded", "message": "slow down"})"));
  EXPECT_EQ(e.code, "overloaded");
  EXPECT_TRUE(std::holds_alternative<UnknownMessage>(ParseServerMessage("{not json")));
  EXPECT_TRUE(std::holds_alternative<UnknownMessage>(ParseServerMessage(R"({"type": "party"})")));
}

}  // namespace
}  // namespace pslam::agent
