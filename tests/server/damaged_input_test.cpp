// A stored input damaged on disk fails its own session with a clear error at the next start; the
// stored inputs stay, and the other sessions in the same database resume untouched.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"
#include "storage/read_pool.hpp"
#include "storage/database.hpp"

namespace pslam::server::testing {
namespace {

std::string StreamSession(WsClient& agent, std::int64_t scans) {
  EXPECT_TRUE(agent.SendJson(Hello()));
  const auto welcome = agent.ReadType("welcome");
  if (!welcome) return "";
  for (std::int64_t seq = 1; seq <= scans; ++seq) EXPECT_TRUE(SendScan(agent, seq, seq % 2 == 0));
  EXPECT_EQ(WaitForAck(agent, scans), scans);
  return (*welcome)["session_id"].get<std::string>();
}

std::string WaitForStatus(unsigned short port, const std::string& id, const std::string& wanted) {
  std::string status;
  for (int i = 0; i < 600 && status != wanted; ++i) {
    status = Get(port, "/api/sessions/" + id).Json().value("status", "");
    if (status != wanted) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return status;
}

TEST(DamagedInputTest, FailsOnlyItsSessionWithAClearErrorAndKeepsTheInputs) {
  TempDir dir;
  const auto data = dir.path() / "data";
  std::string damaged, healthy;
  {
    ServerProcess server(data);
    WsClient first(server.port(), "/api/ingest");
    WsClient second(server.port(), "/api/ingest");
    damaged = StreamSession(first, 20);
    healthy = StreamSession(second, 10);
    ASSERT_FALSE(damaged.empty());
    ASSERT_FALSE(healthy.empty());
    EXPECT_EQ(server.Stop(), 0);
  }
  {
    // Three floats where the session's laser has many more beams: a truncated blob.
    Database db = Database::Open((data / "pslam.sqlite").string(), Database::Mode::kReadWrite);
    const std::vector<std::uint8_t> truncated(3 * sizeof(float), 0);
    Statement update = db.Prepare("UPDATE inputs SET ranges = ? WHERE session_id = ? AND seq = 15");
    update.Bind(1, std::span<const std::uint8_t>(truncated)).Bind(2, damaged).Run();
    Statement changes = db.Prepare("SELECT changes()");
    ASSERT_TRUE(changes.Step());
    ASSERT_EQ(changes.Int(0), 1) << "no stored input 15 to damage";
  }

  ServerProcess restarted(data);
  ASSERT_EQ(WaitForStatus(restarted.port(), damaged, "failed"), "failed");
  const auto events = Get(restarted.port(), "/api/sessions/" + damaged + "/events").Json()["events"];
  std::string error;
  for (const auto& e : events) {
    if (e.value("kind", "") == "engine_failed") error = e["detail"].value("error", "");
  }
  EXPECT_NE(error.find("input 15 is a scan of 3 ranges"), std::string::npos) << events.dump();

  // The agent coming back is told the session failed, not left waiting.
  WsClient agent(restarted.port(), "/api/ingest");
  ASSERT_TRUE(agent.SendJson(Hello(damaged)));
  const auto refusal = agent.ReadType("error", std::chrono::seconds(5));
  ASSERT_TRUE(refusal);
  EXPECT_EQ((*refusal)["code"], "unknown_session");
  EXPECT_NE((*refusal)["message"].get<std::string>().find("has failed"), std::string::npos) << refusal->dump();

  // Nothing stored was lost, and the other session resumed as if nothing happened.
  ReadPool reads(StorageLocation{StorageKind::kSqlite, (data / "pslam.sqlite").string()});
  EXPECT_EQ(reads.Acquire()->repository().LoadInputs(damaged, 0, 100).size(), 20u);
  EXPECT_EQ(WaitForStatus(restarted.port(), healthy, "active"), "active");
  bool processed = false;
  for (int i = 0; i < 600 && !processed; ++i) {
    const auto stats = Get(restarted.port(), "/api/sessions/" + healthy + "/stats").Json();
    processed = stats["filter"].value("processed_seq", 0) >= 10;
    if (!processed) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(processed) << "the healthy session was not rebuilt";
}

}  // namespace
}  // namespace pslam::server::testing
