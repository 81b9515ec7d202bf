// Extend mode end to end: a real server (real SQLite) localizes the scripted robot on a site's map
// of the room as it was, then maps on from it in the room as it is now (the pillar gone, a new
// partition), and closing the session stores the site's next map version, which shows the change.
#include <gtest/gtest.h>

#include <thread>

#include "pslam/io/map_io.hpp"
#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/site_script.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

using ::pslam::testing::Segment;

// The robot's odometry frame is not the map's: odometry = kOdomFrame * true pose.
const Pose2D kOdomFrame(1.5, -2.0, 0.6);
const Eigen::Vector2d kOff(0.013, 0.021);  // RoomWalls() sits off the cell lattice by this

// RoomWalls() as the room is now: the pillar (1.0..1.8 x 0.5..1.3) is gone, and a partition stands
// at x = 3.6 from the south wall to y = -2.6.
std::vector<Segment> ChangedRoom() {
  const auto old = ::pslam::testing::RoomWalls();
  std::vector<Segment> walls(old.begin(), old.begin() + 4);
  walls.insert(walls.end(), old.begin() + 8, old.end());
  walls.push_back({Eigen::Vector2d(3.6, -4.0) + kOff, Eigen::Vector2d(3.6, -2.6) + kOff});
  return walls;
}

void SendChangedScan(WsClient& ws, std::int64_t seq) {
  static const auto walls = ChangedRoom();
  ws.SendJson(ScanJson(ScanInput(seq, seq, walls, kOdomFrame)));
}

nlohmann::json WaitProcessed(unsigned short port, const std::string& id, std::int64_t seq) {
  for (int i = 0; i < 1200; ++i) {
    const auto filter = Get(port, "/api/sessions/" + id + "/stats").Json()["filter"];
    if (filter["processed_seq"] >= seq) return filter;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ADD_FAILURE() << "the engine did not process input " << seq;
  return {};
}

OccupancyGrid VersionMap(unsigned short port, const std::string& site, int version) {
  const std::string base = "/api/sites/" + site + "/maps/" + std::to_string(version);
  return ParseMap(Get(port, base + "/map.yaml").body, Get(port, base + "/map.pgm").body, "version");
}

// The share of cells along a segment (sampled every 2.5 cm) that the map has occupied within one
// cell of the line.
double WallShare(const OccupancyGrid& map, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const int n = static_cast<int>((b - a).norm() / 0.025);
  int walls = 0;
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector2i c = map.WorldToCell(a + (b - a) * (static_cast<double>(i) / n));
    bool wall = false;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) wall |= map.Probability(c.x() + dx, c.y() + dy) > 0.5f;
    }
    walls += wall;
  }
  return static_cast<double>(walls) / (n + 1);
}

nlohmann::json ExtendHello(const std::string& site) {
  const Pose2D start = PoseAt(1) * Pose2D(0.15, -0.1, 0.05);
  return Hello("new", {{"mode", "extend"}, {"site", site}, {"particles", 4}, {"seed", 3}, {"predict", false},
                       {"initial_pose", {{"x", start.x}, {"y", start.y}, {"theta", start.theta}, {"std_xy", 0.2},
                                         {"std_theta", 0.1}}},
                       {"localization", {{"max_particles", 3000}}}});
}

constexpr int kScans = 150;

TEST(ExtendTest, ASessionExtendsTheSitesMapIntoItsNextVersion) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  const std::string site = CreateSite(port, "room");
  ASSERT_EQ(ImportMap(port, site, TrueRoomMap()).status, 201);

  WsClient agent(port, "/api/ingest");
  agent.SendJson(ExtendHello(site));
  const auto welcome = agent.ReadType("welcome");
  ASSERT_TRUE(welcome) << "no welcome";
  const std::string id = (*welcome)["session_id"];
  const auto settings = Get(port, "/api/sessions/" + id).Json()["settings"];
  EXPECT_EQ(settings["mode"], "extend");
  EXPECT_EQ(settings["map_version"], 1);
  for (std::int64_t seq = 1; seq <= kScans; ++seq) SendChangedScan(agent, seq);
  ASSERT_EQ(WaitForAck(agent, kScans), kScans);
  const auto stats = WaitProcessed(port, id, kScans);
  EXPECT_EQ(stats["mode"], "extend_map") << stats;  // localized, then mapping took over
  ASSERT_EQ(Post(port, "/api/sessions/" + id + "/close", "").status, 200);

  const auto versions = Get(port, "/api/sites/" + site + "/maps").Json();
  const auto& list = versions.is_array() ? versions : versions["maps"];
  ASSERT_EQ(list.size(), 2u) << versions;
  const auto latest = Get(port, "/api/sites/" + site + "/maps/2").Json();
  EXPECT_EQ(latest["source"], "session");
  EXPECT_EQ(latest["session_id"], id);
  EXPECT_EQ(latest["extends_version"], 1);
  EXPECT_EQ(Get(port, "/api/sites/" + site).Json()["latest_version"], 2);

  const OccupancyGrid before = VersionMap(port, site, 1), after = VersionMap(port, site, 2);
  // The pillar's south face, seen from the robot's path, and the new partition's west face.
  const Eigen::Vector2d pillar_a = Eigen::Vector2d(1.05, 0.5) + kOff, pillar_b = Eigen::Vector2d(1.75, 0.5) + kOff;
  const Eigen::Vector2d part_a = Eigen::Vector2d(3.6, -3.8) + kOff, part_b = Eigen::Vector2d(3.6, -2.7) + kOff;
  EXPECT_GT(WallShare(before, pillar_a, pillar_b), 0.9);
  EXPECT_LT(WallShare(after, pillar_a, pillar_b), 0.2) << "the pillar that is gone is still in the new version";
  EXPECT_LT(WallShare(before, part_a, part_b), 0.1);
  EXPECT_GT(WallShare(after, part_a, part_b), 0.8) << "the new partition is missing from the new version";
  // What did not change stays: the south wall in front of the robot.
  const Eigen::Vector2d south_a = Eigen::Vector2d(-2.0, -4.0) + kOff, south_b = Eigen::Vector2d(2.0, -4.0) + kOff;
  EXPECT_GT(WallShare(after, south_a, south_b), 0.9);
}

TEST(ExtendTest, AResumedSessionRebuildsTheSameMap) {
  TempDir dir;
  std::string site, uninterrupted, resumed;
  {
    ServerProcess server(dir.path() / "data");
    const unsigned short port = server.port();
    site = CreateSite(port, "room");
    ASSERT_EQ(ImportMap(port, site, TrueRoomMap()).status, 201);
    for (std::string* id : {&uninterrupted, &resumed}) {
      WsClient agent(port, "/api/ingest");
      agent.SendJson(ExtendHello(site));
      *id = (*agent.ReadType("welcome"))["session_id"];
      for (std::int64_t seq = 1; seq <= kScans; ++seq) SendChangedScan(agent, seq);
      ASSERT_EQ(WaitForAck(agent, kScans), kScans);
      WaitProcessed(port, *id, kScans);
    }
    ASSERT_EQ(Post(port, "/api/sessions/" + uninterrupted + "/close", "").status, 200);
    ASSERT_EQ(server.Stop(), 0);
  }
  // The restarted server rebuilds the other session from its stored inputs.
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  EXPECT_EQ(WaitProcessed(port, resumed, kScans)["mode"], "extend_map");
  ASSERT_EQ(Post(port, "/api/sessions/" + resumed + "/close", "").status, 200);
  const auto versions = Get(port, "/api/sites/" + site + "/maps/3").Json();
  EXPECT_EQ(versions["session_id"], resumed);
  EXPECT_EQ(versions["extends_version"], 1);
  const std::string base = "/api/sites/" + site + "/maps/";
  EXPECT_EQ(Get(port, base + "2/map.pgm").body, Get(port, base + "3/map.pgm").body)
      << "the rebuilt session's map differs from the same inputs' uninterrupted one";
}

}  // namespace
}  // namespace pslam::server::testing
