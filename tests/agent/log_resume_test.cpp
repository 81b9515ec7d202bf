// A log replay restarted mid-log against the real pslam-server continues after what the previous
// run spooled (no scan stored twice, time never jumps back), and the finished replay closes its
// session so it no longer holds a running slot on the server.
#ifdef PSLAM_SERVER_BINARY

#include <gtest/gtest.h>

#include <atomic>
#include <nlohmann/json.hpp>
#include <thread>

#include "agent.hpp"
#include "server/support/server_process.hpp"
#include "server_rest.hpp"
#include "sources/log_source.hpp"
#include "temp_dir.hpp"
#include "testing/shared_data.hpp"
#include "wait_for.hpp"

namespace pslam::agent {
namespace {

using server::testing::ServerProcess;
using testing::TempDir;
using testing::GetJson;
using testing::WaitFor;

TEST(LogResumeTest, RestartedReplayContinuesAfterWhatItSpooledAndClosesItsSession) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--particles", "4", "--predict", "off", "--max-sessions", "1"});
  constexpr std::size_t kScans = 150;
  AgentOptions o;
  o.server_host = "127.0.0.1";
  o.server_port = std::to_string(server.port());
  o.spool_dir = (dir.path() / "spool").string();
  o.status_period_s = 2.0;
  o.source = SourceKind::kLog;
  o.rate = 5.0;

  std::string first_session;
  {
    Agent agent(o, std::make_unique<LogSource>(LogSourceOptions{log.string(), o.rate, kScans}));
    std::atomic<bool> stop{false};
    std::thread runner([&] { agent.Run(stop); });
    const bool midway = WaitFor([&] { return agent.link_status().acked_wire_seq > 80; }, 60.0);
    stop = true;  // the operator restarts the agent mid-log
    runner.join();
    ASSERT_TRUE(midway);
    ASSERT_LT(agent.stats().scans, kScans);
    first_session = agent.link_status().session_id;
  }

  Agent agent(o, std::make_unique<LogSource>(LogSourceOptions{log.string(), o.rate, kScans}));
  std::atomic<bool> stop{false};
  int exit_code = -1;
  std::thread runner([&] { exit_code = agent.Run(stop); });
  const bool finished = WaitFor([&] { return exit_code != -1; }, 90.0);
  if (!finished) stop = true;
  runner.join();
  ASSERT_TRUE(finished) << "the restarted replay did not finish";
  EXPECT_EQ(exit_code, kExitOk);
  EXPECT_EQ(agent.link_status().session_id, first_session);  // resumed, not a new session
  EXPECT_LT(agent.stats().scans, kScans);                     // only the rest of the log was read out

  // The finished replay closed its session: final trajectory written, slot free.
  const auto session = GetJson(server.port(), "/api/sessions/" + first_session);
  EXPECT_EQ(session["status"], "closed") << session.dump();
  const auto poses = GetJson(server.port(), "/api/sessions/" + first_session + "/trajectory")["poses"];
  EXPECT_EQ(poses.size(), kScans) << "scans stored twice or lost";
  std::size_t backwards = 0;
  for (std::size_t i = 1; i < poses.size(); ++i) backwards += poses[i]["t"] <= poses[i - 1]["t"] ? 1 : 0;
  EXPECT_EQ(backwards, 0u) << "time jumps back: the log was sent again from the top";
  EXPECT_EQ(GetJson(server.port(), "/api/health")["running_sessions"], 0);
}

}  // namespace
}  // namespace pslam::agent

#endif  // PSLAM_SERVER_BINARY
