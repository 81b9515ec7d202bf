// Poisoned input: odometry no robot could report, and far jumps that would make a map of the space
// between. The server refuses what is implausible, fails (only) the session whose map would outgrow
// its memory limit, frees its running slot, records why, and never rebuilds it at a restart.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"
#include "storage/database.hpp"

namespace pslam::server::testing {
namespace {

constexpr long kRssBoundKib = 1L << 20;  // 1 GiB: generous for four particles and a small room

long RssKib(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;  // gone
}

std::string Open(WsClient& agent, const nlohmann::json& settings) {
  agent.SendJson(Hello("new", settings));
  const auto welcome = agent.ReadType("welcome");
  return welcome ? (*welcome)["session_id"].get<std::string>() : "";
}

std::string ErrorAfter(WsClient& agent, const std::string& text, bool binary = false) {
  binary ? agent.SendBinary(text) : agent.SendText(text);
  const auto error = agent.ReadType("error", std::chrono::seconds(10));
  return error ? (*error)["code"].get<std::string>() + ": " + (*error)["message"].get<std::string>() : "no error";
}

// Polls the session until it has 'wanted' status, failing early if the server's RSS passes the
// bound (the old behaviour: gigabytes within seconds) or the server dies.
std::string WaitForStatus(const ServerProcess& server, const std::string& id, const std::string& wanted, long* peak_kib) {
  std::string status;
  for (int i = 0; i < 600 && status != wanted; ++i) {
    const long rss = RssKib(server.pid());
    *peak_kib = std::max(*peak_kib, rss);
    if (rss < 0) return "server gone";
    if (rss > kRssBoundKib) return "RSS " + std::to_string(rss) + " KiB";
    const auto reply = Get(server.port(), "/api/sessions/" + id);
    if (reply.status == 200) status = reply.Json().value("status", "");
    if (status != wanted) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return status;
}

// A scan 20 km and 20 km further than the last (millimetres sent as metres), at a pace that is
// physically possible (1000 s later): admitted, and the map cannot hold it.
InputRecord FarJump(std::int64_t seq) {
  InputRecord in = ScanInput(seq, seq);
  in.x += 20000.0;
  in.y += 20000.0;
  in.t += 1000.0;
  return in;
}

TEST(PoisonTest, AbsurdOdometryIsRefusedWithoutLosingAnythingAndSurvivesARestart) {
  TempDir dir;
  const auto data = dir.path() / "data";
  std::string id;
  {
    ServerProcess server(data);
    WsClient agent(server.port(), "/api/ingest");
    id = Open(agent, {{"particles", 4}, {"seed", 7}, {"threads", 2}});
    ASSERT_FALSE(id.empty());
    for (int seq = 1; seq <= 5; ++seq) ASSERT_TRUE(SendScan(agent, seq, seq % 2 == 0));
    ASSERT_EQ(WaitForAck(agent, 5), 5);

    InputRecord far = ScanInput(6, 6);
    far.x = far.y = 1e15;
    EXPECT_NE(ErrorAfter(agent, ScanJson(far).dump()).find("bad_message: scan 6: odometry (1e+15, 1e+15"),
              std::string::npos);
    EXPECT_NE(ErrorAfter(agent, EncodeBinaryScan(far), true).find("is beyond 1e+07 m"), std::string::npos);
    nlohmann::json odom = OdomJson(6, 6);
    odom["x"] = -1e15;
    EXPECT_NE(ErrorAfter(agent, odom.dump()).find("bad_message: odom 6"), std::string::npos);
    InputRecord far_range = ScanInput(6, 6);
    far_range.ranges[3] = 3e5f;
    EXPECT_NE(ErrorAfter(agent, EncodeBinaryScan(far_range), true).find("range of 300000 m"), std::string::npos);
    // 20 km in a tenth of a second: refused, and the agent may send the corrected scan.
    InputRecord jump = ScanInput(6, 6);
    jump.x += 20000.0;
    EXPECT_NE(ErrorAfter(agent, ScanJson(jump).dump()).find("faster than 50 m/s"), std::string::npos);
    WsClient other(server.port(), "/api/ingest");
    nlohmann::json bad_offset = Hello();
    bad_offset["laser"]["offset"]["x"] = 1e15;
    EXPECT_NE(ErrorAfter(other, bad_offset.dump()).find("offset"), std::string::npos);

    ASSERT_TRUE(SendScan(agent, 6, false));
    EXPECT_EQ(WaitForAck(agent, 6), 6);
    const auto stats = Get(server.port(), "/api/sessions/" + id + "/stats").Json();
    EXPECT_EQ(stats["ingest"]["acked_seq"], 6);
    EXPECT_EQ(Get(server.port(), "/api/health").status, 200);
    EXPECT_EQ(server.Stop(), 0);
  }
  // Nothing poisoned was stored: the session resumes where it was, and the server stays up.
  ServerProcess restarted(data);
  WsClient agent(restarted.port(), "/api/ingest");
  agent.SendJson(Hello(id));
  const auto welcome = agent.ReadType("welcome");
  ASSERT_TRUE(welcome);
  EXPECT_EQ((*welcome)["last_acked_seq"], 6);
  ASSERT_TRUE(SendScan(agent, 7, true));
  EXPECT_EQ(WaitForAck(agent, 7), 7);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  EXPECT_EQ(Get(restarted.port(), "/api/health").status, 200);
  EXPECT_EQ(Get(restarted.port(), "/api/sessions/" + id).Json()["status"], "active");
}

// Two sessions whose maps would outgrow the default memory limit fail on their own, with the
// reason recorded; RSS stays bounded; their slots are free for the next agent (--max-sessions 2);
// restarts (resume or close) leave them failed instead of rebuilding them.
TEST(PoisonTest, FarJumpFailsOnlyItsSessionWithinTheMemoryLimitAndFreesItsSlot) {
  TempDir dir;
  const auto data = dir.path() / "data";
  std::string failed[2];
  {
    ServerProcess server(data, {"--max-sessions", "2"});
    long peak_kib = 0;
    for (std::string& id : failed) {
      WsClient agent(server.port(), "/api/ingest");
      id = Open(agent, {{"particles", 4}, {"seed", 7}, {"threads", 2}});
      ASSERT_FALSE(id.empty());
      for (int seq = 1; seq <= 5; ++seq) ASSERT_TRUE(SendScan(agent, seq, false));
      ASSERT_EQ(WaitForAck(agent, 5), 5);
      ASSERT_TRUE(agent.SendJson(ScanJson(FarJump(6))));
      ASSERT_EQ(WaitForStatus(server, id, "failed", &peak_kib), "failed");
      const auto session = Get(server.port(), "/api/sessions/" + id).Json();
      EXPECT_NE(session["failure"].get<std::string>().find("memory limit"), std::string::npos) << session.dump();
      // The agent is told, and cannot resume it.
      const auto told = agent.ReadType("error", std::chrono::seconds(10));
      ASSERT_TRUE(told);
      EXPECT_EQ((*told)["code"], "engine_failed");
      WsClient again(server.port(), "/api/ingest");
      again.SendJson(Hello(id));
      const auto refusal = again.ReadType("error", std::chrono::seconds(5));
      ASSERT_TRUE(refusal);
      EXPECT_NE((*refusal)["message"].get<std::string>().find("has failed: memory limit"), std::string::npos)
          << refusal->dump();
    }
    EXPECT_LT(peak_kib, kRssBoundKib);
    std::printf("server peak RSS while two sessions failed: %ld KiB\n", peak_kib);
    EXPECT_EQ(Get(server.port(), "/api/health").Json()["running_sessions"], 0);
    // Both slots are free again.
    WsClient third(server.port(), "/api/ingest");
    EXPECT_FALSE(Open(third, {{"particles", 4}}).empty());
    WsClient fourth(server.port(), "/api/ingest");
    EXPECT_FALSE(Open(fourth, {{"particles", 4}}).empty());
    EXPECT_EQ(server.Stop(), 0);
  }
  for (const std::vector<std::string>& args : {std::vector<std::string>{}, std::vector<std::string>{"--on-restart", "close"}}) {
    ServerProcess restarted(data, args);
    std::this_thread::sleep_for(std::chrono::seconds(1));
    for (const std::string& id : failed) {
      const auto session = Get(restarted.port(), "/api/sessions/" + id).Json();
      EXPECT_EQ(session["status"], "failed");
      EXPECT_NE(session["failure"].get<std::string>().find("memory limit"), std::string::npos);
    }
    const auto health = Get(restarted.port(), "/api/health");
    ASSERT_EQ(health.status, 200);
    EXPECT_EQ(restarted.Stop(), 0);
  }
}

// A session whose rebuild of the same stored inputs took the server down at three start-ups in a
// row (counted in the database before each rebuild) is quarantined: marked failed with the
// reason, not rebuilt.
TEST(PoisonTest, SessionWhoseRebuildNeverCompletesIsQuarantined) {
  TempDir dir;
  const auto data = dir.path() / "data";
  std::string id;
  {
    ServerProcess server(data);
    WsClient agent(server.port(), "/api/ingest");
    id = Open(agent, {{"particles", 4}, {"seed", 7}});
    for (int seq = 1; seq <= 5; ++seq) ASSERT_TRUE(SendScan(agent, seq, false));
    ASSERT_EQ(WaitForAck(agent, 5), 5);
    EXPECT_EQ(server.Stop(), 0);
  }
  const auto rebuilds = [&] {
    Database db = Database::Open((data / "pslam.sqlite").string(), Database::Mode::kReadWrite);
    Statement s = db.Prepare("SELECT rebuilds FROM sessions WHERE id = ?");
    s.Bind(1, id);
    return s.Step() ? s.Int(0) : -1;
  };
  {
    // A restart whose rebuild completes leaves no count behind.
    ServerProcess server(data);
    long peak = 0;
    ASSERT_EQ(WaitForStatus(server, id, "active", &peak), "active");
    for (int i = 0; i < 100 && rebuilds() != 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_EQ(rebuilds(), 0);
    server.Kill9();
  }
  {
    // Three start-ups died rebuilding, but more inputs were stored since: not the same poison.
    Database db = Database::Open((data / "pslam.sqlite").string(), Database::Mode::kReadWrite);
    db.Exec("UPDATE sessions SET rebuilds = 3, rebuild_seq = 4");
  }
  {
    ServerProcess server(data);
    long peak = 0;
    ASSERT_EQ(WaitForStatus(server, id, "active", &peak), "active");
    for (int i = 0; i < 100 && rebuilds() != 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_EQ(rebuilds(), 0);
    server.Kill9();
  }
  {
    Database db = Database::Open((data / "pslam.sqlite").string(), Database::Mode::kReadWrite);
    db.Exec("UPDATE sessions SET rebuilds = 3, rebuild_seq = 5");  // three start-ups died rebuilding these 5
  }
  ServerProcess server(data);
  long peak = 0;
  ASSERT_EQ(WaitForStatus(server, id, "failed", &peak), "failed");
  const auto session = Get(server.port(), "/api/sessions/" + id).Json();
  EXPECT_NE(session["failure"].get<std::string>().find("quarantined"), std::string::npos) << session.dump();
  EXPECT_EQ(Get(server.port(), "/api/health").Json()["running_sessions"], 0);
}

}  // namespace
}  // namespace pslam::server::testing
