// The live view: a snapshot on subscribe, then tiles (binary, zlib), pose, trajectory and stats;
// a viewer that does not read does not hold up the filter or the other viewers.
#include <gtest/gtest.h>

#include <cstring>
#include <thread>

#include "common/zlib_codec.hpp"
#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

TEST(LiveTest, SnapshotThenDeltasAndSlowViewersDoNotStallAnything) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  WsClient agent(port, "/api/ingest");
  agent.SendJson(Hello());
  const std::string id = (*agent.ReadType("welcome"))["session_id"];
  for (std::int64_t seq = 1; seq <= 10; ++seq) SendScan(agent, seq, false);
  ASSERT_EQ(WaitForAck(agent, 10), 10);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // a live tick has happened

  WsClient stalled(port, "/api/sessions/" + id + "/live");  // never reads until the end
  WsClient viewer(port, "/api/sessions/" + id + "/live");
  ASSERT_TRUE(viewer.open());
  auto first = viewer.Read();
  ASSERT_TRUE(first && !first->binary);
  const auto snapshot = first->Json();
  ASSERT_EQ(snapshot["type"], "snapshot");
  EXPECT_EQ(snapshot["session_id"], id);
  EXPECT_EQ(snapshot["tile_size"], 64);
  EXPECT_EQ(snapshot["trajectory"]["poses"].size(), 10u);
  const int tiles = snapshot["tile_count"];
  ASSERT_GT(tiles, 0);
  for (int i = 0; i < tiles; ++i) {
    auto tile = viewer.Read();
    ASSERT_TRUE(tile && tile->binary);
    ASSERT_EQ(tile->data.substr(0, 4), "PSTL");
    std::uint16_t size = 0;
    std::memcpy(&size, tile->data.data() + 12, 2);
    EXPECT_EQ(size, 64);
    const auto* payload = reinterpret_cast<const std::uint8_t*>(tile->data.data()) + 24;
    const auto cells = ZlibDecompress({payload, tile->data.size() - 24}, 64 * 64);
    ASSERT_TRUE(cells);
    EXPECT_EQ(cells->size(), 64u * 64u);
  }
  // New scans arrive as deltas.
  for (std::int64_t seq = 11; seq <= 60; ++seq) SendScan(agent, seq, true);
  ASSERT_EQ(WaitForAck(agent, 60), 60);
  auto trajectory = viewer.ReadType("trajectory");
  ASSERT_TRUE(trajectory);
  EXPECT_GE((*trajectory)["first_index"].get<int>(), 10);
  EXPECT_TRUE(viewer.ReadType("pose"));
  EXPECT_TRUE(viewer.ReadType("stats"));
  // The stalled viewer did not slow the filter: it has processed everything.
  bool processed = false;
  for (int i = 0; i < 400 && !processed; ++i) {
    processed = Get(port, "/api/sessions/" + id + "/stats").Json()["filter"]["processed_seq"] == 60;
    if (!processed) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(processed);
  // The stalled viewer still gets a consistent, coalesced picture when it reads.
  auto late = stalled.Read();
  ASSERT_TRUE(late);
  EXPECT_EQ(late->Json()["type"], "snapshot");
  // Closing the session is announced to viewers.
  ASSERT_EQ(Post(port, "/api/sessions/" + id + "/close", "").status, 200);
  auto ended = viewer.ReadType("session");
  ASSERT_TRUE(ended);
  EXPECT_EQ((*ended)["status"], "closed");
}

TEST(LiveTest, AClosedSessionGetsAStoredSnapshot) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  WsClient agent(server.port(), "/api/ingest");
  agent.SendJson(Hello());
  const std::string id = (*agent.ReadType("welcome"))["session_id"];
  for (std::int64_t seq = 1; seq <= 8; ++seq) SendScan(agent, seq, false);
  ASSERT_EQ(WaitForAck(agent, 8), 8);
  ASSERT_EQ(Post(server.port(), "/api/sessions/" + id + "/close", "").status, 200);
  WsClient viewer(server.port(), "/api/sessions/" + id + "/live");
  auto snapshot = viewer.ReadType("snapshot");
  ASSERT_TRUE(snapshot);
  EXPECT_EQ((*snapshot)["status"], "closed");
  EXPECT_EQ((*snapshot)["trajectory"]["poses"].size(), 8u);
  EXPECT_GT((*snapshot)["tile_count"].get<int>(), 0);
}

}  // namespace
}  // namespace pslam::server::testing
