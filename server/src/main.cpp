// pslam-server: the P-SLAM mapping service (HTTP + WebSocket on Boost.Beast, SQLite storage).
#include <csignal>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "app.hpp"
#include "config/server_options.hpp"

int main(int argc, char** argv) {
  namespace server = pslam::server;
  // A viewer or agent that vanishes mid-write must not kill the process.
  std::signal(SIGPIPE, SIG_IGN);
  const std::vector<std::string> args(argv + 1, argv + argc);
  std::error_code ec;
  const std::filesystem::path program = std::filesystem::canonical("/proc/self/exe", ec);
  auto parsed = server::ParseCommandLine(args, ec ? std::filesystem::current_path() : program.parent_path());
  if (!parsed) {
    std::cerr << "pslam-server: " << parsed.error() << "\n" << server::kUsage;
    return 2;
  }
  if (parsed.value().help) {
    std::cout << server::kUsage;
    return 0;
  }
  auto app = server::App::Create(std::move(parsed.value().options));
  if (!app) {
    std::cerr << "pslam-server: " << app.error() << "\n";
    return 1;
  }
  return app.value()->Run();
}
