// The whole agent (source -> spool -> link) against the fake ingest server.
#include "agent.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "closed_port.hpp"
#include "fakes/fake_ingest_server.hpp"
#include "sources/log_source.hpp"
#include "sources/sim_source.hpp"
#include "temp_dir.hpp"
#include "testing/shared_data.hpp"
#include "wait_for.hpp"

namespace pslam::agent {
namespace {

using testing::FakeIngestServer;
using testing::TempDir;
using testing::WaitFor;

AgentOptions Options(unsigned short port, const TempDir& dir) {
  AgentOptions o;
  o.server_host = "127.0.0.1";
  o.server_port = std::to_string(port);
  o.token = "secret";
  o.spool_dir = (dir.path() / "spool").string();
  o.status_period_s = 2.0;
  return o;
}

TEST(AgentTest, IntelLogSliceArrivesExactlyOnceAcrossServerRestarts) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  constexpr std::size_t kScans = 400;
  // The reference: what the log source yields on its own.
  std::vector<double> expected_scan_times;
  std::size_t expected_odometry = 0;
  {
    LogSource reference({log.string(), 0.0, kScans});
    while (auto e = reference.Next(1.0)) {
      if (auto* s = std::get_if<LaserScan>(&*e)) {
        expected_scan_times.push_back(s->timestamp);
      } else {
        ++expected_odometry;
      }
    }
  }
  ASSERT_EQ(expected_scan_times.size(), kScans);

  AgentOptions o = Options(port, dir);
  o.source = SourceKind::kLog;
  o.source_target = log.string();
  o.rate = 40.0;  // the slice (~90 s of log) in a couple of seconds: time to kill the server mid-stream
  o.max_scans = kScans;
  Agent agent(o, std::make_unique<LogSource>(LogSourceOptions{log.string(), o.rate, kScans}));
  std::atomic<bool> stop{false};
  int exit_code = -1;
  std::thread runner([&] { exit_code = agent.Run(stop); });
  ASSERT_TRUE(WaitFor([&] { return server.sessions().size() == 1 && server.sessions().begin()->second.last_acked > 100; }, 20.0));
  server.Kill();
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // the agent keeps reading its source
  server.Start(port);
  ASSERT_TRUE(WaitFor([&] { return exit_code != -1; }, 60.0)) << "agent did not finish";
  runner.join();
  EXPECT_EQ(exit_code, kExitOk);

  const auto sessions = server.sessions();
  ASSERT_EQ(sessions.size(), 1u);
  const auto& session = sessions.begin()->second;
  EXPECT_EQ(session.gaps, 0u);
  EXPECT_EQ(session.bad_messages, 0u);
  std::vector<double> scan_times;
  std::size_t odometry = 0;
  for (std::size_t i = 0; i < session.committed.size(); ++i) {
    ASSERT_EQ(session.committed[i].seq, i + 1);
    if (session.committed[i].type == "scan") {
      scan_times.push_back(session.committed[i].t);
      EXPECT_EQ(session.committed[i].ranges, 180u);  // Intel FLASER lines: 180 beams
    } else {
      ++odometry;
    }
  }
  EXPECT_EQ(scan_times, expected_scan_times);  // every scan exactly once, in order, original stamps
  EXPECT_EQ(odometry, expected_odometry);
  EXPECT_EQ(session.hello["laser"]["beams"], 180);
  EXPECT_GE(agent.link_status().connections, 2u);
}

TEST(AgentTest, RefusedTokenStopsTheAgentWithAClearExitCode) {
  TempDir dir;
  FakeIngestServer server;
  const auto port = server.Start();
  AgentOptions o = Options(port, dir);
  o.token = "not-the-token";
  SimSourceOptions sim;
  sim.rate = 1.0;
  Agent agent(o, std::make_unique<SimSource>(sim));
  std::atomic<bool> stop{false};
  EXPECT_EQ(agent.Run(stop), kExitRefused);
}

TEST(AgentTest, FullSpoolOfALiveSourceIsCountedAndReported) {
  TempDir dir;
  const testing::ClosedPort closed;  // the link is down throughout
  AgentOptions o = Options(closed.port(), dir);
  // ~100 records (scans and odometry, about 0.4 KiB each): full within about a second even when a
  // loaded machine simulates only 40 scans a second.
  o.spool_max_mb = 0.04;
  o.drive = false;
  SimSourceOptions sim;
  sim.rate = 0.0;  // flat out
  Agent agent(o, std::make_unique<SimSource>(sim));
  std::atomic<bool> stop{false};
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::seconds(3));
    stop = true;
  });
  EXPECT_EQ(agent.Run(stop), kExitOk);
  stopper.join();
  EXPECT_GT(agent.stats().dropped_spool_full, 0u);
  EXPECT_LE(agent.spool_stats().bytes, agent.spool_stats().max_bytes);
  EXPECT_GT(agent.spool_stats().unacked_records, 50u);
}

}  // namespace
}  // namespace pslam::agent
