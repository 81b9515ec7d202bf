// Ingest over the real server: acknowledged means stored, resends are idempotent, kill -9 loses
// nothing acknowledged, a restarted server resumes the session from its stored inputs, an agent
// that outruns the filter is paused and resumed (never dropped), and the agent gets targets.
#include <gtest/gtest.h>

#include <csignal>
#include <thread>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"
#include "storage/read_pool.hpp"

namespace pslam::server::testing {
namespace {

std::string OpenSession(WsClient& agent, const std::string& session = "new", std::int64_t expect_acked = 0) {
  EXPECT_TRUE(agent.SendJson(Hello(session)));
  auto welcome = agent.ReadType("welcome");
  EXPECT_TRUE(welcome) << "no welcome";
  if (!welcome) return "";
  EXPECT_EQ((*welcome)["last_acked_seq"].get<std::int64_t>(), expect_acked);
  return (*welcome)["session_id"].get<std::string>();
}

// Waits until the session's filter has processed 'seq' (stats.filter.processed_seq).
bool WaitProcessed(unsigned short port, const std::string& id, std::int64_t seq, int seconds = 30) {
  for (int i = 0; i < seconds * 20; ++i) {
    const auto stats = Get(port, "/api/sessions/" + id + "/stats").Json();
    if (stats["filter"].value("processed_seq", 0) >= seq) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

TEST(IngestTest, AcknowledgedInputsAreInTheDatabase) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  WsClient agent(server.port(), "/api/ingest");
  ASSERT_TRUE(agent.open());
  const std::string id = OpenSession(agent);
  ASSERT_EQ(id.rfind("s-", 0), 0u);
  std::int64_t seq = 0;
  for (int i = 0; i < 30; ++i) {
    ASSERT_TRUE(SendScan(agent, ++seq, i % 2 == 1));  // JSON and binary scans
    if (i % 5 == 0) {
      ASSERT_TRUE(agent.SendJson(OdomJson(++seq, i)));
    }
  }
  ASSERT_EQ(WaitForAck(agent, seq), seq);
  // Acknowledged means committed: a separate connection to the file sees every input.
  ReadPool reads(StorageLocation{StorageKind::kSqlite, (dir.path() / "data" / "pslam.sqlite").string()});
  auto lease = reads.Acquire();
  EXPECT_EQ(lease->repository().LastInputSeq(id), seq);
  EXPECT_EQ(lease->repository().LoadInputs(id, 0, 1000).size(), static_cast<std::size_t>(seq));
  EXPECT_EQ(lease->repository().CountScans(id), 30);
  // Exploration targets may arrive between the acks; anything else (an error) is a failure.
  for (const auto& m : agent.skipped) EXPECT_EQ(m.value("type", ""), "target") << m.dump();
}

TEST(IngestTest, ResentInputsAreIgnoredButAcknowledgedAgain) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  WsClient agent(server.port(), "/api/ingest");
  const std::string id = OpenSession(agent);
  for (std::int64_t seq = 1; seq <= 12; ++seq) ASSERT_TRUE(SendScan(agent, seq, false));
  ASSERT_EQ(WaitForAck(agent, 12), 12);
  // The agent did not see the acks (say) and resends 5..12, then continues.
  for (std::int64_t seq = 5; seq <= 12; ++seq) ASSERT_TRUE(SendScan(agent, seq, seq % 2 == 0));
  auto again = agent.ReadType("ack");
  ASSERT_TRUE(again);
  EXPECT_GE((*again)["seq"].get<std::int64_t>(), 5);
  for (std::int64_t seq = 13; seq <= 16; ++seq) ASSERT_TRUE(SendScan(agent, seq, false));
  ASSERT_EQ(WaitForAck(agent, 16), 16);
  const auto closed = Post(server.port(), "/api/sessions/" + id + "/close", "");
  ASSERT_EQ(closed.status, 200) << closed.body;
  // Exactly once into the filter: 16 scans, 16 trajectory poses.
  const auto stats = Get(server.port(), "/api/sessions/" + id + "/stats").Json();
  EXPECT_EQ(stats["filter"]["scans"].get<int>(), 16) << stats.dump();
  const auto trajectory = Get(server.port(), "/api/sessions/" + id + "/trajectory").Json();
  EXPECT_EQ(trajectory["poses"].size(), 16u);
  EXPECT_EQ(Get(server.port(), "/api/sessions/" + id).Json()["last_seq"].get<int>(), 16);
}

TEST(IngestTest, OutOfOrderSeqIsRefusedAndTheSocketStaysOpen) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  WsClient agent(server.port(), "/api/ingest");
  OpenSession(agent);
  ASSERT_TRUE(SendScan(agent, 1, false));
  ASSERT_TRUE(SendScan(agent, 3, false));  // 2 is missing
  auto error = agent.ReadType("error");
  ASSERT_TRUE(error);
  EXPECT_EQ((*error)["code"], "bad_message");
  EXPECT_NE((*error)["message"].get<std::string>().find("expected 2"), std::string::npos);
  ASSERT_TRUE(SendScan(agent, 2, false));
  ASSERT_EQ(WaitForAck(agent, 2), 2);
}

TEST(IngestTest, KillNineLosesNothingAcknowledgedAndTheSessionResumes) {
  TempDir dir;
  std::string id;
  std::int64_t acked = 0;
  {
    ServerProcess server(dir.path() / "data");
    WsClient agent(server.port(), "/api/ingest");
    id = OpenSession(agent);
    // Stream without waiting, reading acks as they come, and kill the server mid-stream.
    std::int64_t seq = 0;
    for (int i = 0; i < 60; ++i) {
      ASSERT_TRUE(SendScan(agent, ++seq, i % 2 == 0));
      if (i == 40) {
        acked = WaitForAck(agent, 30);
        ASSERT_GE(acked, 30);
      }
    }
    while (auto m = agent.Read(std::chrono::milliseconds(5))) {
      if (!m->binary && m->Json()["type"] == "ack") acked = std::max(acked, m->Json()["seq"].get<std::int64_t>());
    }
    server.Kill9();
  }
  ServerProcess restarted(dir.path() / "data");
  const auto session = Get(restarted.port(), "/api/sessions/" + id);
  ASSERT_EQ(session.status, 200);
  EXPECT_EQ(session.Json()["status"], "active");
  const std::int64_t stored = session.Json()["last_seq"].get<std::int64_t>();
  EXPECT_GE(stored, acked) << "an acknowledged input was lost";
  // The agent reconnects: the server says what it has, the agent resends the rest.
  WsClient agent(restarted.port(), "/api/ingest");
  EXPECT_EQ(OpenSession(agent, id, stored), id);
  for (std::int64_t seq = stored + 1; seq <= 70; ++seq) ASSERT_TRUE(SendScan(agent, seq, false));
  ASSERT_EQ(WaitForAck(agent, 70), 70);
  ASSERT_TRUE(WaitProcessed(restarted.port(), id, 70));
  ASSERT_EQ(Post(restarted.port(), "/api/sessions/" + id + "/close", "").status, 200);
  const auto stats = Get(restarted.port(), "/api/sessions/" + id + "/stats").Json();
  EXPECT_EQ(stats["filter"]["scans"].get<int>(), 70) << "the rebuilt filter saw every stored input once";
  EXPECT_EQ(Get(restarted.port(), "/api/sessions/" + id + "/trajectory").Json()["poses"].size(), 70u);
}

TEST(IngestTest, GracefulShutdownKeepsTheSessionForTheNextStart) {
  TempDir dir;
  std::string id;
  {
    ServerProcess server(dir.path() / "data");
    WsClient agent(server.port(), "/api/ingest");
    id = OpenSession(agent);
    for (std::int64_t seq = 1; seq <= 10; ++seq) ASSERT_TRUE(SendScan(agent, seq, false));
    ASSERT_EQ(WaitForAck(agent, 10), 10);
    EXPECT_EQ(server.Stop(SIGINT), 0);
    // The server said goodbye: going away (1001).
    while (agent.Read(std::chrono::seconds(2))) {
    }
    EXPECT_TRUE(agent.closed());
  }
  ServerProcess restarted(dir.path() / "data");
  ASSERT_TRUE(WaitProcessed(restarted.port(), id, 10));
  EXPECT_EQ(Get(restarted.port(), "/api/sessions/" + id).Json()["status"], "active");
}

TEST(IngestTest, AFloodOfScansIsPausedAndResumedUntilEveryOneIsAcknowledged) {
  TempDir dir;
  // A small in-flight limit, so the filter falls behind and the ingest has to pause the agent.
  ServerProcess server(dir.path() / "data", {"--max-inflight", "8"});
  WsClient agent(server.port(), "/api/ingest");
  const std::string id = OpenSession(agent);
  constexpr std::int64_t kScans = 400;
  for (std::int64_t seq = 1; seq <= kScans; ++seq) ASSERT_TRUE(SendScan(agent, seq, true)) << "send " << seq;
  EXPECT_EQ(WaitForAck(agent, kScans, std::chrono::seconds(60)), kScans);
  EXPECT_TRUE(agent.open());
  int overloaded = 0;
  for (const auto& m : agent.skipped) {
    if (m.value("type", "") == "error") {
      EXPECT_EQ(m.value("code", ""), "overloaded") << m.dump();
      ++overloaded;
    }
  }
  EXPECT_GE(overloaded, 1) << "the agent was never paused: the test did not exercise back-pressure";
  EXPECT_TRUE(WaitProcessed(server.port(), id, kScans));
}

TEST(IngestTest, TheAgentIsSentExplorationTargets) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  WsClient agent(server.port(), "/api/ingest");
  OpenSession(agent);
  for (std::int64_t seq = 1; seq <= 40; ++seq) ASSERT_TRUE(SendScan(agent, seq, true));
  ASSERT_EQ(WaitForAck(agent, 40), 40);
  std::optional<nlohmann::json> target;
  for (const auto& m : agent.skipped) {
    if (m.value("type", "") == "target") target = m;
  }
  if (!target) target = agent.ReadType("target");
  ASSERT_TRUE(target) << "no target within 10 s of the last ack";
  EXPECT_TRUE((*target)["target"].contains("x"));
  EXPECT_TRUE((*target)["path"].is_array());
}

}  // namespace
}  // namespace pslam::server::testing
