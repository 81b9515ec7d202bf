// Localize mode end to end: a real server localizes the scripted robot on a site's map (one built
// by an earlier session, or the room's true map imported), from a pose in the settings, from one
// set over REST, or globally; the live view shows the fixed map and the particle cloud.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <thread>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/site_script.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

// The robot's odometry frame is not the map's: odometry = kOdomFrame * true pose.
const Pose2D kOdomFrame(1.5, -2.0, 0.6);

void SendLocalizeScan(WsClient& ws, std::int64_t seq) {
  static const auto walls = ::pslam::testing::RoomWalls();
  ws.SendJson(ScanJson(ScanInput(seq, seq, walls, kOdomFrame)));
}

void WaitProcessed(unsigned short port, const std::string& id, std::int64_t seq) {
  for (int i = 0; i < 1200; ++i) {
    if (Get(port, "/api/sessions/" + id + "/stats").Json()["filter"]["processed_seq"] >= seq) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  FAIL() << "the engine did not process input " << seq;
}

struct PoseError {
  double metres = 0.0, degrees = 0.0;
};

// The session's stored estimate at scan 'index' against the truth on the map: 'map_frame' * true pose.
PoseError ErrorAt(const nlohmann::json& poses, std::size_t index, const Pose2D& map_frame = Pose2D()) {
  const auto& p = poses.at(index);
  const Pose2D truth = map_frame * PoseAt(p["seq"].get<std::int64_t>());
  const double dtheta = std::remainder(p["theta"].get<double>() - truth.theta, 2.0 * std::numbers::pi);
  return {std::hypot(p["x"].get<double>() - truth.x, p["y"].get<double>() - truth.y), std::abs(dtheta) * 180.0 / std::numbers::pi};
}

nlohmann::json InitialPoseAt(const Pose2D& p, double std_xy = 0.2) {
  return {{"x", p.x}, {"y", p.y}, {"theta", p.theta}, {"std_xy", std_xy}, {"std_theta", 0.1}};
}

TEST(LocalizeTest, TracksOnAMapBuiltByAnEarlierSessionAndShowsTheFixedMap) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  const std::string site = CreateSite(port, "room");
  const std::string mapping = MapRoomSession(port, site);
  ASSERT_EQ(Post(port, "/api/sites/" + site + "/maps", nlohmann::json{{"session_id", mapping}}.dump()).status, 201);

  // A session's map has the robot's first pose at its origin. Started 0.3 m and 6 degrees off.
  const Pose2D map_frame = PoseAt(1).inverse();
  const Pose2D start = map_frame * PoseAt(1) * Pose2D(0.25, -0.15, 0.1);
  WsClient agent(port, "/api/ingest");
  agent.SendJson(Hello("new", {{"mode", "localize"}, {"site", site}, {"initial_pose", InitialPoseAt(start, 0.3)},
                               {"localization", {{"max_particles", 5000}}}}));
  const auto welcome = agent.ReadType("welcome");
  ASSERT_TRUE(welcome) << "no welcome";
  const std::string id = (*welcome)["session_id"];
  const auto settings = Get(port, "/api/sessions/" + id).Json()["settings"];
  EXPECT_EQ(settings["mode"], "localize");
  EXPECT_EQ(settings["map_version"], 1);  // the latest, named for good

  constexpr int kScans = 150;
  for (std::int64_t seq = 1; seq <= kScans; ++seq) SendLocalizeScan(agent, seq);
  ASSERT_EQ(WaitForAck(agent, kScans), kScans);
  WaitProcessed(port, id, kScans);
  const auto stats = Get(port, "/api/sessions/" + id + "/stats").Json()["filter"];
  EXPECT_EQ(stats["mode"], "localize");
  EXPECT_TRUE(stats["localization"]["localized"].get<bool>()) << stats;
  EXPECT_LT(stats["localization"]["position_std_m"].get<double>(), 0.15) << stats;
  // A figure for the notes, not a check: filter time per scan, localizing and mapping (4 particles).
  std::cout << "step ms per scan: localize " << stats["step_ms_mean"] << ", mapping "
            << Get(port, "/api/sessions/" + mapping + "/stats").Json()["filter"]["step_ms_mean"] << "\n";

  // The live view: the site's map, the particle cloud and the pose.
  WsClient viewer(port, "/api/sessions/" + id + "/live");
  const auto snapshot = viewer.ReadType("snapshot");
  ASSERT_TRUE(snapshot);
  EXPECT_GT((*snapshot)["tile_count"].get<int>(), 0);
  EXPECT_GT((*snapshot)["particles"].size(), 100u);
  EXPECT_EQ((*snapshot)["stats"]["mode"], "localize");
  // Mapping sessions take no pose.
  EXPECT_EQ(Post(port, "/api/sessions/" + mapping + "/initial_pose", R"({"x": 0, "y": 0})").status, 409);

  ASSERT_EQ(Post(port, "/api/sessions/" + id + "/close", "").status, 200);
  // The map shown is the fixed map, not a new one.
  EXPECT_EQ(Get(port, "/api/sessions/" + id + "/map.pgm").body, Get(port, "/api/sites/" + site + "/maps/1/map.pgm").body);
  const auto poses = Get(port, "/api/sessions/" + id + "/trajectory").Json()["poses"];
  ASSERT_EQ(poses.size(), static_cast<std::size_t>(kScans));
  double worst_m = 0.0, worst_deg = 0.0, sum_m = 0.0;
  for (std::size_t i = 50; i < poses.size(); ++i) {
    const PoseError e = ErrorAt(poses, i, map_frame);
    worst_m = std::max(worst_m, e.metres);
    worst_deg = std::max(worst_deg, e.degrees);
    sum_m += e.metres;
  }
  EXPECT_LT(sum_m / 100.0, 0.08);  // the map is a 4-particle session's, with its own small errors
  EXPECT_LT(worst_m, 0.2);
  EXPECT_LT(worst_deg, 4.0);
}

TEST(LocalizeTest, APoseSetOverRestRelocalizesARobotStartedWrong) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  const std::string site = CreateSite(port, "room");
  ASSERT_EQ(ImportMap(port, site, TrueRoomMap()).status, 201);

  // Started 2.5 m off, sure of it, and without random injection: nothing but the operator helps.
  const Pose2D wrong = PoseAt(1) * Pose2D(0.0, 2.5, 0.0);
  WsClient agent(port, "/api/ingest");
  agent.SendJson(Hello("new", {{"mode", "localize"}, {"site", site}, {"initial_pose", InitialPoseAt(wrong, 0.05)},
                               {"localization", {{"max_particles", 3000},
                                                 {"recovery_alpha_slow", 0.0},
                                                 {"recovery_alpha_fast", 0.0}}}}));
  const std::string id = (*agent.ReadType("welcome"))["session_id"];
  for (std::int64_t seq = 1; seq <= 40; ++seq) SendLocalizeScan(agent, seq);
  ASSERT_EQ(WaitForAck(agent, 40), 40);
  WaitProcessed(port, id, 40);

  EXPECT_EQ(Post(port, "/api/sessions/" + id + "/initial_pose", R"({"y": 1})").status, 400);  // x is required
  const auto set = Post(port, "/api/sessions/" + id + "/initial_pose", InitialPoseAt(PoseAt(41), 0.2).dump());
  ASSERT_EQ(set.status, 200) << set.body;
  for (std::int64_t seq = 41; seq <= 150; ++seq) SendLocalizeScan(agent, seq);
  ASSERT_EQ(WaitForAck(agent, 150), 150);
  ASSERT_EQ(Post(port, "/api/sessions/" + id + "/close", "").status, 200);

  const auto poses = Get(port, "/api/sessions/" + id + "/trajectory").Json()["poses"];
  ASSERT_EQ(poses.size(), 150u);
  EXPECT_GT(ErrorAt(poses, 35).metres, 1.0);  // still where it was told it started
  for (std::size_t i = 100; i < 150; ++i) EXPECT_LT(ErrorAt(poses, i).metres, 0.1) << "scan " << i;
  bool logged = false;
  const auto events = Get(port, "/api/sessions/" + id + "/events").Json()["events"];
  for (const auto& e : events) logged |= e["kind"] == "initial_pose";
  EXPECT_TRUE(logged) << events;
  EXPECT_EQ(Post(port, "/api/sessions/" + id + "/initial_pose", InitialPoseAt(PoseAt(1)).dump()).status, 409);  // closed
}

TEST(LocalizeTest, APoseSetOverRestIsAppliedAgainWhenTheSessionIsRebuilt) {
  TempDir dir;
  std::string site, id;
  const nlohmann::json settings = {{"mode", "localize"},
                                   {"initial_pose", InitialPoseAt(PoseAt(1) * Pose2D(0.0, 2.5, 0.0), 0.05)},
                                   {"localization", {{"max_particles", 3000},
                                                     {"recovery_alpha_slow", 0.0},
                                                     {"recovery_alpha_fast", 0.0}}}};
  {
    ServerProcess server(dir.path() / "data");
    const unsigned short port = server.port();
    site = CreateSite(port, "room");
    ASSERT_EQ(ImportMap(port, site, TrueRoomMap()).status, 201);
    nlohmann::json with_site = settings;
    with_site["site"] = site;
    WsClient agent(port, "/api/ingest");
    agent.SendJson(Hello("new", with_site));
    id = (*agent.ReadType("welcome"))["session_id"];
    for (std::int64_t seq = 1; seq <= 40; ++seq) SendLocalizeScan(agent, seq);
    ASSERT_EQ(WaitForAck(agent, 40), 40);
    WaitProcessed(port, id, 40);
    ASSERT_EQ(Post(port, "/api/sessions/" + id + "/initial_pose", InitialPoseAt(PoseAt(41), 0.2).dump()).status, 200);
    for (std::int64_t seq = 41; seq <= 120; ++seq) SendLocalizeScan(agent, seq);
    ASSERT_EQ(WaitForAck(agent, 120), 120);
    WaitProcessed(port, id, 120);
    ASSERT_EQ(server.Stop(), 0);  // not closed: the restarted server rebuilds it from its inputs
  }
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  WaitProcessed(port, id, 120);
  ASSERT_EQ(Post(port, "/api/sessions/" + id + "/close", "").status, 200);
  const auto poses = Get(port, "/api/sessions/" + id + "/trajectory").Json()["poses"];
  ASSERT_EQ(poses.size(), 120u);
  EXPECT_GT(ErrorAt(poses, 35).metres, 1.0);  // the rebuild starts wrong, as the session did
  for (std::size_t i = 90; i < 120; ++i) EXPECT_LT(ErrorAt(poses, i).metres, 0.1) << "scan " << i;
  int logged = 0;
  const auto events = Get(port, "/api/sessions/" + id + "/events").Json()["events"];
  for (const auto& e : events) {
    if (e["kind"] != "initial_pose") continue;
    ++logged;
    EXPECT_EQ(e["detail"]["seq"], 41) << e;
  }
  EXPECT_EQ(logged, 1) << events;  // applied once, and not logged again by the rebuild
}

TEST(LocalizeTest, GlobalLocalizationWithoutAPose) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  const std::string site = CreateSite(port, "room");
  ASSERT_EQ(ImportMap(port, site, TrueRoomMap()).status, 201);

  WsClient agent(port, "/api/ingest");
  agent.SendJson(Hello("new", {{"mode", "localize"}, {"site", site}}));
  const std::string id = (*agent.ReadType("welcome"))["session_id"];
  constexpr int kScans = 150;  // 12 m of travel
  constexpr int kFirst = 5;    // under a metre: too little seen to search the map yet
  for (std::int64_t seq = 1; seq <= kFirst; ++seq) SendLocalizeScan(agent, seq);
  ASSERT_EQ(WaitForAck(agent, kFirst), kFirst);
  WaitProcessed(port, id, kFirst);
  const auto early = Get(port, "/api/sessions/" + id + "/stats").Json()["filter"]["localization"];
  EXPECT_FALSE(early["localized"].get<bool>()) << early;
  EXPECT_EQ(early["place"], "searching") << early;
  for (std::int64_t seq = kFirst + 1; seq <= kScans; ++seq) SendLocalizeScan(agent, seq);
  ASSERT_EQ(WaitForAck(agent, kScans), kScans);
  WaitProcessed(port, id, kScans);
  const auto stats = Get(port, "/api/sessions/" + id + "/stats").Json()["filter"];
  EXPECT_TRUE(stats["localization"]["localized"].get<bool>()) << stats;
  EXPECT_EQ(stats["localization"]["place"], "") << stats;  // recognized: tracking
  // While it searched, the robot was asked once to turn all the way round in place.
  std::vector<double> turns;
  for (const auto& m : agent.skipped) {
    if (m.value("type", "") == "target" && m.contains("turn")) turns.push_back(m["turn"].get<double>());
  }
  ASSERT_EQ(turns.size(), 1u);
  EXPECT_NEAR(turns[0], 2.0 * std::numbers::pi, 1e-9);
  ASSERT_EQ(Post(port, "/api/sessions/" + id + "/close", "").status, 200);
  const auto poses = Get(port, "/api/sessions/" + id + "/trajectory").Json()["poses"];
  ASSERT_EQ(poses.size(), static_cast<std::size_t>(kScans));
  for (std::size_t i = kScans - 30; i < kScans; ++i) EXPECT_LT(ErrorAt(poses, i).metres, 0.2) << "scan " << i;
}

}  // namespace
}  // namespace pslam::server::testing
