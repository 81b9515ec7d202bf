// A fleet of real pslam-server nodes on one real PostgreSQL server (started by the ctest fixture on
// loopback): new sessions placed on the least loaded node with the agent following the redirect, a
// node killed with SIGKILL mid-stream and its session taken over by another node once the lease
// expires, with every scan filtered exactly once and only one node ever running the session; a node
// that joins late is handed one of a crowded node's sessions, again with every scan filtered once.
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
using server::testing::TestPostgresDatabase;
using testing::TempDir;
using testing::WaitFor;

constexpr const char* kAgentToken = "agent-secret-1";
constexpr const char* kViewerToken = "viewer-secret-1";

nlohmann::json GetJson(unsigned short port, const std::string& target) {
  return testing::GetJson(port, target, kViewerToken);
}

std::vector<std::string> NodeArgs(const TestPostgresDatabase& db, const std::string& node_id) {
  return {"--agent-token", kAgentToken, "--viewer-token", kViewerToken, "--particles", "4", "--predict", "off",
          "--postgres", db.url(), "--node-id", node_id, "--lease-seconds", "2"};
}

std::string Address(const ServerProcess& node) { return "127.0.0.1:" + std::to_string(node.port()); }

// The sessions each node says it runs, by node id, from GET /api/cluster.
std::map<std::string, std::vector<std::string>> SessionsByNode(unsigned short port) {
  std::map<std::string, std::vector<std::string>> out;
  const nlohmann::json cluster = GetJson(port, "/api/cluster");
  for (const auto& node : cluster["nodes"]) {
    out[node["node_id"].get<std::string>()] = node["sessions"].get<std::vector<std::string>>();
  }
  return out;
}

AgentOptions SimOptions(const std::string& servers, const std::filesystem::path& spool) {
  const ParsedOptions parsed = ParseAgentOptions({"--server", servers, "--token", kAgentToken, "--source", "sim",
                                                  "--spool", spool.string(), "--no-drive", "--rate", "2"});
  if (!parsed.options) throw std::runtime_error(parsed.error);
  return *parsed.options;
}

TEST(FleetTest, NewSessionsArePlacedOnTheLeastLoadedNodeAndAgentsFollowTheRedirect) {
  TempDir dir;
  TestPostgresDatabase db;
  ServerProcess a(dir.path() / "a", NodeArgs(db, "node-a"));
  ServerProcess b(dir.path() / "b", NodeArgs(db, "node-b"));
  ASSERT_TRUE(WaitFor([&] { return GetJson(a.port(), "/api/cluster")["nodes"].size() == 2; }, 10.0));

  // Both idle: the first stays where it connected; the second is sent to the idle node.
  std::vector<std::unique_ptr<Agent>> agents;
  std::atomic<bool> stop{false};
  std::vector<std::thread> runners;
  struct JoinAtExit {
    std::atomic<bool>& stop;
    std::vector<std::thread>& threads;
    ~JoinAtExit() {
      stop = true;
      for (auto& t : threads) {
        if (t.joinable()) t.join();
      }
    }
  } join_at_exit{stop, runners};
  for (int i = 0; i < 2; ++i) {
    agents.push_back(std::make_unique<Agent>(SimOptions(Address(a), dir.path() / ("spool" + std::to_string(i))),
                                             std::make_unique<SimSource>(SimSourceOptions{})));
    runners.emplace_back([&, agent = agents.back().get()] { agent->Run(stop); });
    ASSERT_TRUE(WaitFor([&] { return agents.back()->link_status().acked_wire_seq > 5; }, 20.0)) << "agent " << i;
  }
  const std::string first = agents[0]->link_status().session_id;
  const std::string second = agents[1]->link_status().session_id;
  auto sessions = SessionsByNode(b.port());
  EXPECT_EQ(sessions["node-a"], std::vector<std::string>{first});
  EXPECT_EQ(sessions["node-b"], std::vector<std::string>{second});
  EXPECT_EQ(GetJson(b.port(), "/api/cluster")["mode"], "fleet");
  // Any node answers REST for any session from the shared database.
  EXPECT_EQ(GetJson(b.port(), "/api/sessions/" + first)["status"], "active");

  // A write to a session another node runs is redirected there.
  const auto close = testing::Request(b.port(), "POST", "/api/sessions/" + first + "/close", kAgentToken);
  EXPECT_EQ(close.status, 307);
  EXPECT_EQ(close.headers.at("Location"), "http://" + Address(a) + "/api/sessions/" + first + "/close");

  // The simulator's agents close their sessions as they stop; the second one asks node A, which
  // sends it on to node B.
  stop = true;
  for (auto& t : runners) t.join();
  EXPECT_EQ(GetJson(a.port(), "/api/sessions/" + first)["status"], "closed");
  EXPECT_EQ(GetJson(a.port(), "/api/sessions/" + second)["status"], "closed");
}

TEST(FleetTest, NodeKilledMidStreamItsSessionMovesAndEveryScanIsFilteredOnce) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  TempDir dir;
  TestPostgresDatabase db;
  auto a = std::make_unique<ServerProcess>(dir.path() / "a", NodeArgs(db, "node-a"));
  ServerProcess b(dir.path() / "b", NodeArgs(db, "node-b"));
  const unsigned short a_port = a->port();

  constexpr std::size_t kScans = 300;
  AgentOptions o = SimOptions(Address(*a) + "," + Address(b), dir.path() / "spool");
  o.source = SourceKind::kLog;
  o.rate = 20.0;
  Agent agent(o, std::make_unique<LogSource>(LogSourceOptions{log.string(), o.rate, kScans}));
  std::atomic<bool> stop{false};
  int exit_code = -1;
  std::thread runner([&] { exit_code = agent.Run(stop); });
  struct JoinAtExit {
    std::atomic<bool>& stop;
    std::thread& thread;
    ~JoinAtExit() {
      stop = true;
      if (thread.joinable()) thread.join();
    }
  } join_at_exit{stop, runner};

  ASSERT_TRUE(WaitFor([&] { return agent.link_status().acked_wire_seq > 150; }, 30.0));
  const std::string session = agent.link_status().session_id;
  ASSERT_EQ(SessionsByNode(b.port())["node-a"], std::vector<std::string>{session});
  a->Kill9();
  const auto killed = std::chrono::steady_clock::now();

  // Node B takes the session over once the 2 s lease expires; the agent finds B on its own.
  ASSERT_TRUE(WaitFor([&] { return SessionsByNode(b.port())["node-b"] == std::vector<std::string>{session}; }, 15.0));
  const double moved_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
  std::cout << "session owned again " << moved_s << " s after the kill (lease 2 s)\n";
  const auto lease = GetJson(b.port(), "/api/cluster")["leases"];
  ASSERT_EQ(lease.size(), 1u);
  EXPECT_EQ(lease[0]["node_id"], "node-b");
  EXPECT_EQ(lease[0]["epoch"], 2);  // one change of owner

  const bool finished = WaitFor([&] { return exit_code != -1; }, 90.0);
  if (!finished) stop = true;
  runner.join();
  ASSERT_TRUE(finished) << "the agent did not get everything acknowledged";
  EXPECT_EQ(exit_code, kExitOk);
  const LinkStatus link = agent.link_status();
  EXPECT_EQ(link.session_id, session);  // resumed, not started anew

  // The agent closed its session at the end of the log, through node B (node A is gone): the
  // final figures are stored.
  const auto row = GetJson(b.port(), "/api/sessions/" + session);
  EXPECT_EQ(row["status"], "closed");
  EXPECT_EQ(row["last_seq"].get<std::uint64_t>(), link.acked_wire_seq);
  const auto stats = GetJson(b.port(), "/api/sessions/" + session + "/stats");
  EXPECT_EQ(stats["filter"]["processed_seq"].get<std::uint64_t>(), link.acked_wire_seq);
  EXPECT_EQ(stats["filter"]["scans"].get<std::uint64_t>(), kScans);  // none lost, none filtered twice

  // Node A back under the same id runs nothing: its earlier leases are gone, not resumed.
  ServerProcess a_again(dir.path() / "a2", [&] {
    auto args = NodeArgs(db, "node-a");
    args.insert(args.end(), {"--listen", "127.0.0.1:" + std::to_string(a_port)});
    return args;
  }());
  std::this_thread::sleep_for(std::chrono::seconds(3));  // over a lease: time for a wrong takeover
  EXPECT_EQ(GetJson(a_again.port(), "/api/health")["running_sessions"], 0);
  EXPECT_EQ(GetJson(a_again.port(), "/api/sessions/" + session)["status"], "closed");
}

TEST(FleetTest, NodeJoiningLateIsHandedASessionAndEveryScanIsFilteredOnce) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  TempDir dir;
  TestPostgresDatabase db;
  ServerProcess a(dir.path() / "a", NodeArgs(db, "node-a"));

  // Two robots on node A, which alone runs both; they know only node A.
  constexpr std::size_t kScans = 400;
  std::vector<std::unique_ptr<Agent>> agents;
  std::vector<int> exit_codes(2, -1);
  std::atomic<bool> stop{false};
  std::vector<std::thread> runners;
  struct JoinAtExit {
    std::atomic<bool>& stop;
    std::vector<std::thread>& threads;
    ~JoinAtExit() {
      stop = true;
      for (auto& t : threads) {
        if (t.joinable()) t.join();
      }
    }
  } join_at_exit{stop, runners};
  for (int i = 0; i < 2; ++i) {
    AgentOptions o = SimOptions(Address(a), dir.path() / ("spool" + std::to_string(i)));
    o.source = SourceKind::kLog;
    o.rate = 10.0;
    agents.push_back(std::make_unique<Agent>(o, std::make_unique<LogSource>(LogSourceOptions{log.string(), o.rate, kScans})));
    runners.emplace_back([&, i, agent = agents.back().get()] { exit_codes[i] = agent->Run(stop); });
  }
  ASSERT_TRUE(WaitFor([&] { return SessionsByNode(a.port())["node-a"].size() == 2; }, 20.0));
  ASSERT_TRUE(WaitFor([&] { return agents[0]->link_status().acked_wire_seq > 20 && agents[1]->link_status().acked_wire_seq > 20; }, 20.0));

  // Node B joins: node A, two sessions ahead, hands it one.
  ServerProcess b(dir.path() / "b", NodeArgs(db, "node-b"));
  ASSERT_TRUE(WaitFor([&] { return SessionsByNode(a.port())["node-b"].size() == 1; }, 20.0))
      << GetJson(a.port(), "/api/cluster").dump();
  const auto sessions = SessionsByNode(b.port());
  EXPECT_EQ(sessions.at("node-a").size(), 1u);

  const bool finished = WaitFor([&] { return exit_codes[0] != -1 && exit_codes[1] != -1; }, 120.0);
  if (!finished) stop = true;
  for (auto& t : runners) t.join();
  ASSERT_TRUE(finished) << "the agents did not get everything acknowledged";
  // Both finished and closed, each scan filtered once, the moved one too (rebuilt on node B).
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(exit_codes[i], kExitOk);
    const LinkStatus link = agents[i]->link_status();
    const auto row = GetJson(b.port(), "/api/sessions/" + link.session_id);
    EXPECT_EQ(row["status"], "closed");
    EXPECT_EQ(row["last_seq"].get<std::uint64_t>(), link.acked_wire_seq);
    const auto stats = GetJson(b.port(), "/api/sessions/" + link.session_id + "/stats");
    EXPECT_EQ(stats["filter"]["processed_seq"].get<std::uint64_t>(), link.acked_wire_seq) << "agent " << i;
    EXPECT_EQ(stats["filter"]["scans"].get<std::uint64_t>(), kScans) << "agent " << i;  // none lost, none twice
  }
}

}  // namespace
}  // namespace pslam::agent

#endif  // PSLAM_SERVER_BINARY
