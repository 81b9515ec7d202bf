// The link against a faithful fake of the ingest protocol (fakes/fake_ingest_server.hpp).
#include "link/server_link.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <optional>
#include <set>
#include <thread>

#include "closed_port.hpp"
#include "fakes/fake_ingest_server.hpp"
#include "link/session_state.hpp"
#include "temp_dir.hpp"
#include "wait_for.hpp"

namespace pslam::agent {
namespace {

using testing::FakeIngestOptions;
using testing::FakeIngestServer;
using testing::FakeSession;
using testing::TempDir;
using testing::WaitFor;

std::vector<std::uint8_t> Message(std::uint64_t i) {
  if (i % 8 == 0) return EncodeRecord(OdomMessage{1000.0 + i * 0.01, 0.1 * i, 0, 0, 0.2, 0});
  ScanMessage s;
  s.t = 1000.0 + i * 0.01;
  s.ranges.assign(181, 3.0f);
  s.ranges[7] = std::numeric_limits<float>::quiet_NaN();
  return EncodeRecord(s);
}

HelloMessage Hello() {
  HelloMessage h;
  h.robot_id = "test-robot";
  h.laser = {-1.5707963, 0.0174533, 181, 8.0, 0.0, Pose2D(0.16, 0, 0)};
  return h;
}

ServerLinkOptions LinkOptions(unsigned short port, const TempDir& dir, std::string token = "secret") {
  ServerLinkOptions o;
  o.host = "127.0.0.1";
  o.port = std::to_string(port);
  o.token = std::move(token);
  o.session_file = dir.path() / "session.json";
  o.backoff_initial_s = 0.05;
  o.backoff_max_s = 0.5;
  return o;
}

SpoolOptions SpoolAt(const TempDir& dir) {
  SpoolOptions o;
  o.directory = dir.path() / "spool";
  o.segment_bytes = 64 << 10;
  return o;
}

// Every seq 1..n stored exactly once, in order, nothing skipped.
void ExpectExactlyOnce(const FakeSession& session, std::uint64_t n) {
  ASSERT_EQ(session.committed.size(), n);
  for (std::uint64_t i = 0; i < n; ++i) ASSERT_EQ(session.committed[i].seq, i + 1);
  EXPECT_EQ(session.gaps, 0u);
  EXPECT_EQ(session.bad_messages, 0u);
}

TEST(ServerLinkTest, StreamsEverythingAndDropsAcknowledgedRecords) {
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  Spool spool(SpoolAt(dir));
  for (std::uint64_t i = 1; i <= 300; ++i) spool.Append(Message(i));
  ServerLink link(LinkOptions(port, dir), spool, Hello());
  link.Start();
  ASSERT_TRUE(WaitFor([&] { return spool.empty_of_unacked(); }, 10.0));
  const auto sessions = server.sessions();
  ASSERT_EQ(sessions.size(), 1u);
  const FakeSession& s = sessions.begin()->second;
  ExpectExactlyOnce(s, 300);
  EXPECT_TRUE(s.committed[0].binary);
  EXPECT_EQ(s.committed[0].ranges, 181u);
  EXPECT_EQ(s.committed[0].null_ranges, 1u);
  EXPECT_EQ(s.committed[7].type, "odom");
  EXPECT_EQ(s.hello["robot_id"], "test-robot");
  EXPECT_EQ(link.status().state, LinkState::kStreaming);
  EXPECT_EQ(link.status().acked_wire_seq, 300u);
  link.Stop();
}

TEST(ServerLinkTest, JsonScansWhenAsked) {
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  Spool spool(SpoolAt(dir));
  for (std::uint64_t i = 1; i <= 20; ++i) spool.Append(Message(i));
  auto options = LinkOptions(port, dir);
  options.binary_scans = false;
  ServerLink link(options, spool, Hello());
  link.Start();
  ASSERT_TRUE(WaitFor([&] { return spool.empty_of_unacked(); }, 5.0));
  const FakeSession s = server.sessions().begin()->second;
  ExpectExactlyOnce(s, 20);
  EXPECT_FALSE(s.committed[0].binary);
  EXPECT_EQ(s.committed[0].null_ranges, 1u);
}

TEST(ServerLinkTest, ServerKilledMidStreamAndRestartedGetsEveryMessageExactlyOnce) {
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  Spool spool(SpoolAt(dir));
  ServerLink link(LinkOptions(port, dir), spool, Hello());
  link.Start();
  // A producer at ~1000 messages/s, never blocked by the link.
  std::atomic<bool> done{false};
  constexpr std::uint64_t kMessages = 3000;
  std::thread producer([&] {
    for (std::uint64_t i = 1; i <= kMessages; ++i) {
      ASSERT_TRUE(spool.Append(Message(i)));
      link.Notify();
      std::this_thread::sleep_for(std::chrono::microseconds(1000));
    }
    done = true;
  });
  ASSERT_TRUE(WaitFor([&] { return link.status().acked_wire_seq > 500; }, 10.0));
  server.Kill();  // mid-stream: some messages received but not committed are lost with it
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  EXPECT_NE(link.status().state, LinkState::kStreaming);
  server.Start(port);
  ASSERT_TRUE(WaitFor([&] { return link.status().acked_wire_seq > 1500; }, 10.0));
  server.Kill();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  server.Start(port);
  producer.join();
  ASSERT_TRUE(WaitFor([&] { return done && spool.empty_of_unacked(); }, 20.0));
  const auto sessions = server.sessions();
  ASSERT_EQ(sessions.size(), 1u);  // resumed, not a new session per reconnect
  ExpectExactlyOnce(sessions.begin()->second, kMessages);
  EXPECT_GE(server.welcomes(), 3u);
  EXPECT_GE(link.status().connections, 3u);
  link.Stop();
}

TEST(ServerLinkTest, AgentRestartResumesItsSession) {
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  {
    Spool spool(SpoolAt(dir));
    for (std::uint64_t i = 1; i <= 50; ++i) spool.Append(Message(i));
    ServerLink link(LinkOptions(port, dir), spool, Hello());
    link.Start();
    ASSERT_TRUE(WaitFor([&] { return spool.empty_of_unacked(); }, 5.0));
  }
  Spool spool(SpoolAt(dir));  // as after a reboot; acks are not persisted in the spool
  for (std::uint64_t i = 51; i <= 80; ++i) spool.Append(Message(i));
  ServerLink link(LinkOptions(port, dir), spool, Hello());
  link.Start();
  ASSERT_TRUE(WaitFor([&] { return spool.empty_of_unacked(); }, 5.0));
  const auto sessions = server.sessions();
  ASSERT_EQ(sessions.size(), 1u);
  ExpectExactlyOnce(sessions.begin()->second, 80);
}

TEST(ServerLinkTest, UnknownSessionStartsANewOneRenumbered) {
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  Spool spool(SpoolAt(dir));
  for (std::uint64_t i = 1; i <= 40; ++i) spool.Append(Message(i));
  spool.Acknowledge(10);  // the first 10 went to a session the server no longer has
  SaveSessionState(dir.path() / "session.json", {"s-gone", 0});
  ServerLink link(LinkOptions(port, dir), spool, Hello());
  link.Start();
  ASSERT_TRUE(WaitFor([&] { return spool.empty_of_unacked(); }, 5.0));
  const auto sessions = server.sessions();
  ASSERT_EQ(sessions.size(), 1u);
  ExpectExactlyOnce(sessions.begin()->second, 30);  // spool seq 11..40 became wire seq 1..30
  EXPECT_EQ(LoadSessionState(dir.path() / "session.json")->seq_base, 10u);
}

TEST(ServerLinkTest, StateFilesWithBadSequenceNumbersAreIgnored) {
  TempDir dir;
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.path() / name) << text;
    return dir.path() / name;
  };
  for (const char* seq : {"-1", "2.5", "-7.66e128", "\"10\""}) {
    EXPECT_FALSE(LoadSessionState(write("session.json", std::string(R"({"session_id": "s-1", "seq_base": )") + seq + "}")))
        << seq;
    EXPECT_FALSE(LoadReplayPosition(write("replay.json", std::string(R"({"log": "a.clf", "first_seq": )") + seq + "}")))
        << seq;
  }
  EXPECT_EQ(LoadSessionState(write("session.json", R"({"session_id": "s-1", "seq_base": 10})"))->seq_base, 10u);
  EXPECT_EQ(LoadReplayPosition(write("replay.json", R"({"log": "a.clf", "first_seq": 3})"))->first_seq, 3u);
}

TEST(ServerLinkTest, RefusedTokenOnUpgradeIsReportedClearlyAndNotRetried) {
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  Spool spool(SpoolAt(dir));
  ServerLink link(LinkOptions(port, dir, "wrong"), spool, Hello());
  link.Start();
  ASSERT_TRUE(WaitFor([&] { return link.refusal().has_value(); }, 5.0));
  EXPECT_NE(link.refusal()->find("refused the agent token (HTTP 401)"), std::string::npos) << *link.refusal();
  EXPECT_EQ(link.status().state, LinkState::kRefused);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(server.refused(), 1u);
}

TEST(ServerLinkTest, RefusedTokenInBandIsReportedClearly) {
  TempDir dir;
  FakeIngestOptions o;
  o.refuse_in_band = true;
  FakeIngestServer server(o);
  const auto port = server.Start();
  Spool spool(SpoolAt(dir));
  ServerLink link(LinkOptions(port, dir, "wrong"), spool, Hello());
  link.Start();
  ASSERT_TRUE(WaitFor([&] { return link.refusal().has_value(); }, 5.0));
  EXPECT_NE(link.refusal()->find("token"), std::string::npos) << *link.refusal();
}

TEST(ServerLinkTest, NoServerMeansBackOffNotBusyLoop) {
  TempDir dir;
  std::optional<testing::ClosedPort> closed(std::in_place);
  const unsigned short port = closed->port();
  Spool spool(SpoolAt(dir));
  auto options = LinkOptions(port, dir);
  options.backoff_initial_s = 0.05;
  options.backoff_max_s = 0.4;
  ServerLink link(options, spool, Hello());
  link.Start();
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto failures = link.status().failures;
  EXPECT_GE(failures, 3u);
  EXPECT_LE(failures, 10u);  // 0.05, 0.1, 0.2, 0.4, 0.4, ... not thousands
  // And it connects once the server appears.
  closed.reset();
  FakeIngestServer server;
  server.Start(port);
  spool.Append(Message(1));
  link.Notify();
  ASSERT_TRUE(WaitFor([&] { return spool.empty_of_unacked(); }, 3.0));
}

TEST(ServerLinkTest, TargetsAreDelivered) {
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  Spool spool(SpoolAt(dir));
  ServerLink link(LinkOptions(port, dir), spool, Hello());
  link.Start();
  ASSERT_TRUE(WaitFor([&] { return link.status().state == LinkState::kStreaming; }, 3.0));
  server.SendToAll(nlohmann::json::parse(
      R"({"type": "target", "target": {"x": 4.5, "y": 2.0}, "path": [[0.0, 0.0], [4.5, 2.0]], "pose": {"x": 0, "y": 0, "theta": 0}})"));
  std::optional<TargetMessage> target;
  ASSERT_TRUE(WaitFor([&] { return (target = link.TakeTarget()).has_value(); }, 3.0));
  EXPECT_EQ(target->path.size(), 2u);
}

}  // namespace
}  // namespace pslam::agent
