#pragma once
// The real pslam-server binary on 127.0.0.1 with a random port (testing/server_launch.hpp), for
// tests that need a server they can kill -9.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "testing/server_launch.hpp"

namespace pslam::server::testing {

class ServerProcess {
 public:
  ServerProcess(const std::filesystem::path& data_dir, const std::vector<std::string>& extra_args = {}) {
    std::vector<std::string> args = {"--checkpoint-seconds", "1"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    log_ = data_dir.parent_path() / (data_dir.filename().string() + ".log");
    const auto server = ::pslam::testing::LaunchServer(PSLAM_SERVER_BINARY, data_dir, args, log_, std::chrono::seconds(20));
    pid_ = server.pid;
    stdout_ = server.stdout_fd;
    port_ = server.port;
  }
  ~ServerProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (stdout_ >= 0) close(stdout_);
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  unsigned short port() const { return port_; }
  pid_t pid() const { return pid_; }
  const std::filesystem::path& log_path() const { return log_; }  // the server's stderr

  // kill -9: no shutdown, no flush, nothing.
  void Kill9() { Signal(SIGKILL); }
  // SIGTERM (or 'signal') and wait; returns the exit status.
  int Stop(int signal = SIGTERM) { return Signal(signal); }

 private:
  int Signal(int signal) {
    if (pid_ <= 0) return -1;
    kill(pid_, signal);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

  pid_t pid_ = -1;
  int stdout_ = -1;
  unsigned short port_ = 0;
  std::filesystem::path log_;
};

}  // namespace pslam::server::testing
