// The lost-filter warning of a live session: the statistics (REST and the live stats message) carry
// the filter's tracking state, and a session event records when the filter became lost, once, not
// again when a restarted server re-runs the stored inputs.
#include <gtest/gtest.h>

#include <csignal>
#include <thread>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

constexpr std::int64_t kInRoom = 60;    // scans of the room the map is built of
constexpr std::int64_t kCarried = 90;   // then, up to this seq, scans of another room

// Scan 'seq' of a robot carried off into another room after kInRoom scans: its laser sees that room,
// its odometry goes on along the same path.
nlohmann::json CarriedOffScan(std::int64_t seq) {
  static const auto other = ::pslam::testing::OtherRoomWalls();
  InputRecord in = ScanInput(seq, seq);
  const Pose2D pose(in.x, in.y, in.theta);
  in.ranges = ::pslam::testing::RenderScan(pose, other, pose).ranges;
  return ScanJson(in);
}

nlohmann::json FilterStats(unsigned short port, const std::string& id) {
  return Get(port, "/api/sessions/" + id + "/stats").Json()["filter"];
}

bool WaitProcessed(unsigned short port, const std::string& id, std::int64_t seq, int seconds = 30) {
  for (int i = 0; i < seconds * 20; ++i) {
    if (FilterStats(port, id).value("processed_seq", 0) >= seq) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

std::vector<nlohmann::json> LostEvents(unsigned short port, const std::string& id) {
  std::vector<nlohmann::json> lost;
  const auto events = Get(port, "/api/sessions/" + id + "/events").Json();
  for (const auto& e : events["events"]) {
    if (e["kind"] == "filter_lost") lost.push_back(e);
  }
  return lost;
}

TEST(LostWarningTest, StatsAndAnEventSayWhenTheFilterIsLost) {
  TempDir dir;
  std::string id;
  {
    ServerProcess server(dir.path() / "data");
    const unsigned short port = server.port();
    WsClient agent(port, "/api/ingest");
    agent.SendJson(Hello());
    id = (*agent.ReadType("welcome"))["session_id"];
    for (std::int64_t seq = 1; seq <= kInRoom; ++seq) SendScan(agent, seq, false);
    ASSERT_EQ(WaitForAck(agent, kInRoom), kInRoom);
    ASSERT_TRUE(WaitProcessed(port, id, kInRoom));
    const auto before = FilterStats(port, id);
    EXPECT_EQ(before["tracking"], "ok");
    EXPECT_EQ(before["tracking_reason"], "");

    WsClient viewer(port, "/api/sessions/" + id + "/live");
    ASSERT_TRUE(viewer.ReadType("snapshot"));
    for (std::int64_t seq = kInRoom + 1; seq <= kCarried; ++seq) agent.SendJson(CarriedOffScan(seq));
    ASSERT_EQ(WaitForAck(agent, kCarried), kCarried);
    ASSERT_TRUE(WaitProcessed(port, id, kCarried));

    const auto after = FilterStats(port, id);
    EXPECT_EQ(after["tracking"], "lost");
    EXPECT_NE(after["tracking_reason"].get<std::string>().find("tracking score"), std::string::npos) << after.dump();
    // Viewers are told live.
    bool told = false;
    while (!told) {
      const auto stats = viewer.ReadType("stats");
      if (!stats) break;
      told = (*stats)["stats"]["tracking"] == "lost";
    }
    EXPECT_TRUE(told) << "no live stats message said the filter is lost";
    // Events are written behind the filter: give the writer a moment.
    for (int i = 0; i < 100 && LostEvents(port, id).empty(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const auto lost = LostEvents(port, id);
    ASSERT_EQ(lost.size(), 1u);
    EXPECT_GT(lost[0]["detail"]["scan_index"].get<int>(), kInRoom - 1);
    EXPECT_LE(lost[0]["detail"]["seq"].get<int>(), kCarried);
    EXPECT_NE(lost[0]["detail"]["reason"].get<std::string>().find("tracking score"), std::string::npos);
    EXPECT_EQ(server.Stop(SIGINT), 0);
  }
  // A restart re-runs the stored inputs through a new filter: the state comes back, the event is
  // not recorded a second time.
  ServerProcess restarted(dir.path() / "data");
  const unsigned short port = restarted.port();
  ASSERT_TRUE(WaitProcessed(port, id, kCarried));
  // Closing drains the filter, and its own event is written after every event before it.
  ASSERT_EQ(Post(port, "/api/sessions/" + id + "/close", "").status, 200);
  EXPECT_EQ(FilterStats(port, id)["tracking"], "lost") << "the closed session's stored statistics";
  EXPECT_EQ(LostEvents(port, id).size(), 1u);
}

}  // namespace
}  // namespace pslam::server::testing
