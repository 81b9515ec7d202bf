// pslam-agent: runs on the robot and streams odometry and scans to pslam-server's ingest WebSocket.
#include <csignal>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "agent.hpp"
#include "agent_options.hpp"
#include "common/log.hpp"
#include "source_factory.hpp"

namespace {

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  using namespace pslam::agent;
  const std::vector<std::string> args(argv + 1, argv + argc);
  const ParsedOptions parsed = ParseAgentOptions(args);
  if (parsed.help) {
    std::cout << AgentUsage();
    return 0;
  }
  if (!parsed.options) {
    std::cerr << "pslam-agent: " << parsed.error << "\n\n" << AgentUsage();
    return 2;
  }
  const AgentOptions& options = *parsed.options;
  SetLogLevel(options.verbose ? LogLevel::kDebug : LogLevel::kInfo);
  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  std::signal(SIGPIPE, SIG_IGN);  // a dead socket is an error code, not a reason to die
  try {
    Agent agent(options, MakeSource(options));
    return agent.Run(g_stop);
  } catch (const std::exception& e) {
    PSLAM_LOG(kError) << e.what();
    return kExitFailure;
  }
}
