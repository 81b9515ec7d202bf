// Every REST endpoint against the real server, and replays: a stored session replayed with the
// same seed reproduces its map; a CARMEN log from the replay directory maps with RPE and KL.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <thread>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"
#include "testing/shared_data.hpp"

namespace pslam::server::testing {
namespace {

// An agent session of 'scans' scans, closed; returns its id.
std::string RecordSession(unsigned short port, int scans, std::int64_t seed = 7) {
  WsClient agent(port, "/api/ingest");
  agent.SendJson(Hello("new", {{"particles", 4}, {"seed", seed}}));
  const auto welcome = agent.ReadType("welcome");
  EXPECT_TRUE(welcome);
  for (std::int64_t seq = 1; seq <= scans; ++seq) SendScan(agent, seq, seq % 3 == 0);
  EXPECT_EQ(WaitForAck(agent, scans), scans);
  const std::string id = (*welcome)["session_id"];
  EXPECT_EQ(Post(port, "/api/sessions/" + id + "/close", "").status, 200);
  return id;
}

nlohmann::json WaitClosed(unsigned short port, const std::string& id, int seconds = 40) {
  for (int i = 0; i < seconds * 20; ++i) {
    const auto s = Get(port, "/api/sessions/" + id).Json();
    if (s["status"] != "active") return s;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return Get(port, "/api/sessions/" + id).Json();
}

TEST(RestTest, EveryEndpointAnswers) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  const std::string id = RecordSession(port, 25);

  EXPECT_EQ(Get(port, "/api/health").Json()["status"], "ok");
  EXPECT_EQ(Get(port, "/api/version").Json()["ingest_protocol"], 1);
  const auto list = Get(port, "/api/sessions?status=closed&limit=10").Json();
  EXPECT_EQ(list["total"], 1);
  EXPECT_EQ(list["sessions"][0]["id"], id);
  EXPECT_EQ(Get(port, "/api/sessions?status=active").Json()["total"], 0);
  EXPECT_EQ(Get(port, "/api/sessions?robot_id=test-bot&name=test").Json()["total"], 1);

  const auto session = Get(port, "/api/sessions/" + id).Json();
  EXPECT_EQ(session["status"], "closed");
  EXPECT_EQ(session["scans"], 25);
  const auto stats = Get(port, "/api/sessions/" + id + "/stats").Json();
  EXPECT_EQ(stats["filter"]["scans"], 25);
  EXPECT_EQ(stats["filter"]["particles"], 4);
  EXPECT_TRUE(stats["predictions"].contains("accepted"));
  EXPECT_TRUE(stats["filter"].contains("predictions_made"));
  EXPECT_EQ(Get(port, "/api/sessions/" + id + "/trajectory?from=20").Json()["poses"].size(), 5u);
  EXPECT_GE(Get(port, "/api/sessions/" + id + "/events").Json()["events"].size(), 2u);

  const auto meta = Get(port, "/api/sessions/" + id + "/map").Json();
  EXPECT_DOUBLE_EQ(meta["resolution"].get<double>(), 0.05);
  ASSERT_FALSE(meta["tiles"].empty());
  auto png = Get(port, "/api/sessions/" + id + "/map.png");
  EXPECT_EQ(png.status, 200);
  EXPECT_EQ(png.headers["Content-Type"], "image/png");
  EXPECT_EQ(png.body.substr(1, 3), "PNG");
  const auto pgm = Get(port, "/api/sessions/" + id + "/map.pgm");
  EXPECT_EQ(pgm.body.substr(0, 2), "P5");
  EXPECT_NE(Get(port, "/api/sessions/" + id + "/map.yaml").body.find("image: map.pgm"), std::string::npos);
  const auto& tile = meta["tiles"][0];
  const auto tile_frame = Get(port, "/api/sessions/" + id + "/map/tiles/" + std::to_string(tile["x"].get<int>()) + "/" +
                                        std::to_string(tile["y"].get<int>()));
  EXPECT_EQ(tile_frame.status, 200);
  EXPECT_EQ(tile_frame.body.substr(0, 4), "PSTL");
  EXPECT_EQ(Get(port, "/api/sessions/" + id + "/map/tiles/9999/9999").status, 404);

  EXPECT_EQ(Get(port, "/api/sessions/" + id + "/hypotheses?status=confirmed&min_psi=0.5&bbox=-1,-1,1,1").Json()["total"], 0);
  EXPECT_EQ(Get(port, "/api/sessions/" + id + "/hypotheses/1").status, 404);
  EXPECT_EQ(Get(port, "/api/sessions/" + id + "/hypotheses/1/overlay.png").status, 404);

  // Create through the API, then delete.
  const auto created = Post(port, "/api/sessions", nlohmann::json{{"name", "api"}, {"laser", LaserJson()}}.dump());
  ASSERT_EQ(created.status, 201) << created.body;
  const std::string api_id = created.Json()["id"];
  EXPECT_EQ(created.Json()["status"], "active");
  EXPECT_EQ(Request(port, "DELETE", "/api/sessions/" + api_id).status, 204);
  EXPECT_EQ(Get(port, "/api/sessions/" + api_id).status, 404);
  EXPECT_EQ(Request(port, "DELETE", "/api/sessions/" + api_id).status, 404);
  EXPECT_EQ(Request(port, "PUT", "/api/sessions/" + id).status, 405);
}

TEST(RestTest, ReplayOfAStoredSessionReproducesItsMapForTheSameSeed) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  const std::string id = RecordSession(port, 40, 11);
  const auto replay = Post(port, "/api/replays", nlohmann::json{{"session", id}, {"settings", {{"seed", 11}}}}.dump());
  ASSERT_EQ(replay.status, 201) << replay.body;
  const std::string replay_id = replay.Json()["id"];
  EXPECT_EQ(replay.Json()["replay_of"], id);
  EXPECT_EQ(WaitClosed(port, replay_id)["status"], "closed");
  EXPECT_EQ(Get(port, "/api/sessions/" + replay_id + "/stats").Json()["filter"]["scans"], 40);
  EXPECT_EQ(Get(port, "/api/sessions/" + replay_id + "/map.pgm").body, Get(port, "/api/sessions/" + id + "/map.pgm").body);
  EXPECT_EQ(Get(port, "/api/sessions/" + replay_id + "/trajectory").body.size(),
            Get(port, "/api/sessions/" + id + "/trajectory").body.size());
}

TEST(RestTest, ReplayOfACarmenLogReportsRpeAndKl) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  PSLAM_REQUIRE_DATA(relations, "intel/intel.relations");
  TempDir dir;
  const auto logs = dir.path() / "logs";
  std::filesystem::create_directories(logs);
  {
    // A slice of the Intel log: its first 400 laser lines (80 s, where the first relations are) and the odometry around them.
    std::ifstream in(log);
    std::ofstream out(logs / "intel-slice.clf");
    std::string line;
    int lasers = 0;
    while (std::getline(in, line) && lasers < 400) {
      out << line << "\n";
      if (line.rfind("FLASER", 0) == 0) ++lasers;
    }
  }
  std::filesystem::copy_file(relations, logs / "intel.relations");
  ServerProcess server(dir.path() / "data", {"--replay-dir", logs.string()});
  const unsigned short port = server.port();
  const auto first = Post(port, "/api/replays", nlohmann::json{{"log", "intel-slice.clf"}, {"settings", {{"particles", 4}}}}.dump());
  ASSERT_EQ(first.status, 201) << first.body;
  const std::string first_id = first.Json()["id"];
  ASSERT_EQ(WaitClosed(port, first_id)["status"], "closed");
  // The first run's map is the reference of the second.
  std::ofstream(logs / "map.pgm", std::ios::binary) << Get(port, "/api/sessions/" + first_id + "/map.pgm").body;
  std::ofstream(logs / "map.yaml") << Get(port, "/api/sessions/" + first_id + "/map.yaml").body;
  const auto second = Post(port, "/api/replays",
                           nlohmann::json{{"log", "intel-slice.clf"}, {"relations", "intel.relations"},
                                          {"reference_map", "map.yaml"}, {"settings", {{"particles", 4}}}}.dump());
  ASSERT_EQ(second.status, 201) << second.body;
  const auto closed = WaitClosed(port, second.Json()["id"]);
  ASSERT_EQ(closed["status"], "closed");
  // Metrics are computed from the stored trajectory once the session has closed.
  nlohmann::json metrics;
  for (int i = 0; i < 200 && !metrics.contains("rpe"); ++i) {
    metrics = Get(port, "/api/sessions/" + closed["id"].get<std::string>() + "/stats").Json()["metrics"];
    if (!metrics.contains("rpe")) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(metrics.contains("rpe")) << metrics.dump();
  EXPECT_GT(metrics["rpe"]["used"].get<int>(), 0);
  ASSERT_TRUE(metrics.contains("kl")) << metrics.dump();
  // The reference is a trinary image (map_server semantics), so even the same map has a finite,
  // non-zero divergence from it; a different map would have a larger one.
  EXPECT_GT(metrics["kl"]["cells"].get<int>(), 1000);
  EXPECT_TRUE(std::isfinite(metrics["kl"]["nats"].get<double>()));
  EXPECT_EQ(Get(port, "/api/sessions/" + first_id + "/stats").Json()["filter"]["scans"], 400);
}

}  // namespace
}  // namespace pslam::server::testing
