// End to end against the real pslam-server binary (built by this project; its path comes from
// CMake as PSLAM_SERVER_BINARY): an Intel log slice streamed by the agent, the server killed with
// SIGKILL mid-stream and restarted on the same port and storage (a SQLite file, or a PostgreSQL
// server on loopback), and every scan stored exactly once.
#ifdef PSLAM_SERVER_BINARY

#include <gtest/gtest.h>

#include <atomic>
#include <nlohmann/json.hpp>
#include <thread>

#include "agent.hpp"
#include "server/support/server_process.hpp"
#include "server/support/test_services.hpp"
#include "server_rest.hpp"
#include "sources/log_source.hpp"
#include "sources/sim_source.hpp"
#include "temp_dir.hpp"
#include "testing/shared_data.hpp"
#include "wait_for.hpp"

namespace pslam::agent {
namespace {

using server::testing::ServerProcess;
using testing::TempDir;
using testing::WaitFor;

nlohmann::json GetJson(unsigned short port, const std::string& target) {
  return testing::GetJson(port, target, "viewer-secret-1");
}

// The server's storage engine: "Sqlite" (its data directory) or "Postgres" (--postgres URL).
class RealServerOnEachStorage : public ::testing::TestWithParam<std::string> {};

INSTANTIATE_TEST_SUITE_P(Engines, RealServerOnEachStorage, ::testing::Values("Sqlite", "Postgres"),
                         [](const auto& info) { return info.param; });

TEST_P(RealServerOnEachStorage, ServerKilledMidStreamAndRestartedStoresEveryScanExactlyOnce) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  TempDir dir;
  const auto data = dir.path() / "data";
  std::vector<std::string> args = {"--agent-token", "agent-secret-1", "--viewer-token", "viewer-secret-1",
                                   "--particles", "4", "--predict", "off"};
  std::optional<server::testing::TestPostgresDatabase> postgres;
  if (GetParam() == "Postgres") {
    postgres.emplace();
    args.insert(args.end(), {"--postgres", postgres->url()});
  }
  auto server = std::make_unique<ServerProcess>(data, args);
  const unsigned short port = server->port();

  constexpr std::size_t kScans = 300;
  AgentOptions o;
  o.server_host = "127.0.0.1";
  o.server_port = std::to_string(port);
  o.token = "agent-secret-1";
  o.spool_dir = (dir.path() / "spool").string();
  o.status_period_s = 2.0;
  o.source = SourceKind::kLog;
  o.rate = 20.0;
  Agent agent(o, std::make_unique<LogSource>(LogSourceOptions{log.string(), o.rate, kScans}));
  std::atomic<bool> stop{false};
  int exit_code = -1;
  std::thread runner([&] { exit_code = agent.Run(stop); });

  ASSERT_TRUE(WaitFor([&] { return agent.link_status().acked_wire_seq > 150; }, 30.0));
  server->Kill9();
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));  // the agent keeps replaying into its spool
  auto restart_args = args;
  restart_args.insert(restart_args.end(), {"--listen", "127.0.0.1:" + std::to_string(port)});
  server = std::make_unique<ServerProcess>(data, restart_args);
  ASSERT_EQ(server->port(), port);

  const bool finished = WaitFor([&] { return exit_code != -1; }, 90.0);
  if (!finished) stop = true;
  runner.join();
  ASSERT_TRUE(finished) << "the agent did not get everything acknowledged";
  EXPECT_EQ(exit_code, kExitOk);
  const LinkStatus link = agent.link_status();
  EXPECT_GE(link.connections, 2u);

  const SpoolStats spool = agent.spool_stats();
  // The filter runs behind the (durable) acks: wait until it has processed everything stored.
  nlohmann::json stats;
  WaitFor(
      [&] {
        stats = GetJson(port, "/api/sessions/" + link.session_id + "/stats");
        return stats["filter"]["processed_seq"] == stats["ingest"]["received_seq"];
      },
      60.0);
  EXPECT_EQ(stats["ingest"]["received_seq"].get<std::uint64_t>(), link.acked_wire_seq);
  EXPECT_EQ(stats["filter"]["processed_seq"], stats["ingest"]["received_seq"]);
  EXPECT_EQ(stats["filter"]["scans"].get<std::uint64_t>(), kScans);  // exactly once: none lost, none doubled
  const auto session = GetJson(port, "/api/sessions/" + link.session_id);
  EXPECT_EQ(session["last_seq"].get<std::uint64_t>(), link.acked_wire_seq);
  EXPECT_EQ(link.acked_wire_seq, spool.next_seq - 1);  // one session from seq 1: wire seq = spool seq
}

TEST(RealServerTest, RefusedTokenIsReportedClearly) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--agent-token", "agent-secret-1"});
  Spool spool(SpoolOptions{dir.path() / "spool"});
  ServerLinkOptions o;
  o.host = "127.0.0.1";
  o.port = std::to_string(server.port());
  o.token = "wrong";
  HelloMessage hello;
  hello.robot_id = "test";
  hello.laser = {-1.5707963, 0.0174533, 181, 8.0, 0.0, Pose2D()};
  ServerLink link(o, spool, hello);
  link.Start();
  ASSERT_TRUE(WaitFor([&] { return link.refusal().has_value(); }, 10.0));
  EXPECT_NE(link.refusal()->find("token"), std::string::npos) << *link.refusal();
  link.Stop();
}

AgentOptions SimAgentOptions(unsigned short port, const std::filesystem::path& spool) {
  AgentOptions o;
  o.server_host = "127.0.0.1";
  o.server_port = std::to_string(port);
  o.token = "agent-secret-1";
  o.spool_dir = spool.string();
  o.source = SourceKind::kSim;
  o.rate = 1.0;
  o.drive = false;
  return o;
}

TEST(RealServerTest, RefusedHelloEndsTheAgentWithItsOwnExitCode) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--agent-token", "agent-secret-1"});
  AgentOptions o = SimAgentOptions(server.port(), dir.path() / "spool");
  o.session_settings_json = R"({"particles": -5})";  // refused by the server, every time
  Agent agent(o, std::make_unique<SimSource>(SimSourceOptions{}));
  std::atomic<bool> stop{false};
  int exit_code = -1;
  std::thread runner([&] { exit_code = agent.Run(stop); });
  const bool ended = WaitFor([&] { return exit_code != -1; }, 20.0);
  if (!ended) stop = true;
  runner.join();
  ASSERT_TRUE(ended) << "the agent kept retrying a hello the server refuses";
  EXPECT_EQ(exit_code, kExitSessionRefused);
  EXPECT_NE(agent.link_status().last_error.find("refused the hello"), std::string::npos) << agent.link_status().last_error;
}

// Runs the simulator agent made from command-line 'flags' until 'messages' of its messages are
// acknowledged, then stops it (a sim agent closes its session); returns the session's id.
std::string RunSimAgent(unsigned short port, const std::filesystem::path& spool, std::vector<std::string> flags,
                        std::uint64_t messages) {
  flags.insert(flags.end(), {"--server", "127.0.0.1:" + std::to_string(port), "--token", "agent-secret-1", "--source",
                             "sim", "--spool", spool.string(), "--no-drive"});
  const ParsedOptions parsed = ParseAgentOptions(flags);
  if (!parsed.options) throw std::runtime_error(parsed.error);
  Agent agent(*parsed.options, std::make_unique<SimSource>(SimSourceOptions{}));
  std::atomic<bool> stop{false};
  std::thread runner([&] { agent.Run(stop); });
  const bool acked = WaitFor([&] { return agent.link_status().acked_wire_seq >= messages; }, 60.0);
  stop = true;
  runner.join();
  if (!acked) throw std::runtime_error("the agent's scans were not acknowledged: " + agent.link_status().last_error);
  return agent.link_status().session_id;
}

TEST(RealServerTest, LocalizeFlagsStartALocalizeSessionOnTheSiteFromTheGivenPose) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--agent-token", "agent-secret-1", "--viewer-token", "viewer-secret-1",
                                             "--particles", "4", "--predict", "off"});
  const unsigned short port = server.port();
  const std::string site = testing::PostJson(port, "/api/sites", {{"name", "sim"}}, "agent-secret-1")["id"];
  // The site's map: a first run of the same simulated robot, mapping into the site.
  const std::string mapping = RunSimAgent(port, dir.path() / "spool-map", {"--site", site}, 30);
  EXPECT_EQ(GetJson(port, "/api/sessions/" + mapping)["settings"]["site"], site);
  WaitFor([&] { return GetJson(port, "/api/sessions/" + mapping)["status"] == "closed"; }, 20.0);
  testing::PostJson(port, "/api/sites/" + site + "/maps", {{"session_id", mapping}}, "agent-secret-1");

  // A session's map has the robot's first pose at its origin: the second run starts about there.
  const std::string id = RunSimAgent(port, dir.path() / "spool-localize",
                                     {"--mode", "localize", "--site", site, "--initial-pose", "0.05,-0.02,0.01"}, 20);
  const auto settings = GetJson(port, "/api/sessions/" + id)["settings"];
  EXPECT_EQ(settings["mode"], "localize");
  EXPECT_EQ(settings["site"], site);
  EXPECT_EQ(settings["map_version"], 1);
  ASSERT_TRUE(settings["initial_pose"].is_object()) << settings;
  EXPECT_DOUBLE_EQ(settings["initial_pose"]["x"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(settings["initial_pose"]["y"].get<double>(), -0.02);
  EXPECT_NEAR(settings["initial_pose"]["theta"].get<double>(), 0.01, 1e-9);  // normalized by the server
  const auto filter = GetJson(port, "/api/sessions/" + id + "/stats")["filter"];
  EXPECT_EQ(filter["mode"], "localize");
  EXPECT_TRUE(filter.contains("localization")) << filter;
}

TEST(RealServerTest, ExtendFlagsStartAnExtendSessionOnTheSite) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--agent-token", "agent-secret-1", "--viewer-token", "viewer-secret-1",
                                             "--particles", "4", "--predict", "off"});
  const unsigned short port = server.port();
  const std::string site = testing::PostJson(port, "/api/sites", {{"name", "sim"}}, "agent-secret-1")["id"];
  const std::string mapping = RunSimAgent(port, dir.path() / "spool-map", {"--site", site}, 30);
  WaitFor([&] { return GetJson(port, "/api/sessions/" + mapping)["status"] == "closed"; }, 20.0);
  testing::PostJson(port, "/api/sites/" + site + "/maps", {{"session_id", mapping}}, "agent-secret-1");

  const std::string id = RunSimAgent(port, dir.path() / "spool-extend",
                                     {"--mode", "extend", "--site", site, "--initial-pose", "0.05,-0.02,0.01"}, 20);
  const auto settings = GetJson(port, "/api/sessions/" + id)["settings"];
  EXPECT_EQ(settings["mode"], "extend");
  EXPECT_EQ(settings["site"], site);
  EXPECT_EQ(settings["map_version"], 1);
  const std::string phase = GetJson(port, "/api/sessions/" + id + "/stats")["filter"]["mode"];
  EXPECT_TRUE(phase == "extend_localize" || phase == "extend_map") << phase;
}

TEST(RealServerTest, SessionLimitIsReportedPlainlyAndRetried) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--agent-token", "agent-secret-1", "--viewer-token", "viewer-secret-1",
                                             "--max-sessions", "1", "--particles", "4"});
  // Another agent holds the only session slot.
  AgentOptions other = SimAgentOptions(server.port(), dir.path() / "spool-other");
  Agent holder(other, std::make_unique<SimSource>(SimSourceOptions{}));
  std::atomic<bool> stop_holder{false};
  std::thread holder_runner([&] { holder.Run(stop_holder); });
  ASSERT_TRUE(WaitFor([&] { return holder.link_status().connections > 0; }, 20.0));

  ::testing::internal::CaptureStderr();
  Agent agent(SimAgentOptions(server.port(), dir.path() / "spool"), std::make_unique<SimSource>(SimSourceOptions{}));
  std::atomic<bool> stop{false};
  int exit_code = -1;
  std::thread runner([&] { exit_code = agent.Run(stop); });
  std::this_thread::sleep_for(std::chrono::seconds(3));
  const bool retrying = exit_code == -1;
  // Once the slot is free, the retry gets in.
  const std::string holder_session = holder.link_status().session_id;
  stop_holder = true;
  holder_runner.join();
  const auto closed = testing::Request(server.port(), "POST", "/api/sessions/" + holder_session + "/close", "agent-secret-1");
  ASSERT_EQ(closed.status, 200) << closed.body;
  const bool connected = WaitFor([&] { return agent.link_status().connections > 0; }, 20.0);
  stop = true;
  runner.join();
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_TRUE(retrying) << "the agent gave up on a transient refusal";
  EXPECT_TRUE(connected);
  EXPECT_NE(log.find("server refused: the server runs its maximum of sessions (overloaded)"), std::string::npos) << log;
  EXPECT_EQ(log.find("cannot reach"), std::string::npos) << log;
}

}  // namespace
}  // namespace pslam::agent

#endif  // PSLAM_SERVER_BINARY
