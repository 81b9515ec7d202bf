#pragma once
// The real pslam-server binary, started with fork/exec on 127.0.0.1 with a random port, for tests
// that need a server they can kill -9. The port is read from the server's "listening on" line.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "testing/listening_port.hpp"

namespace pslam::server::testing {

class ServerProcess {
 public:
  ServerProcess(const std::filesystem::path& data_dir, const std::vector<std::string>& extra_args = {}) {
    int out[2];
    if (pipe(out) != 0) throw std::runtime_error("pipe failed");
    std::vector<std::string> args = {PSLAM_SERVER_BINARY, "--listen", "127.0.0.1:0", "--data", data_dir.string(),
                                     "--checkpoint-seconds", "1"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    const std::string log = (data_dir.parent_path() / (data_dir.filename().string() + ".log")).string();
    pid_ = fork();
    if (pid_ == 0) {
      dup2(out[1], STDOUT_FILENO);
      const int err = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (err >= 0) dup2(err, STDERR_FILENO);
      close(out[0]);
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    close(out[1]);
    stdout_ = out[0];
    port_ = ReadPort();
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

  unsigned short ReadPort() {
    return ::pslam::testing::ReadListeningPort(stdout_, std::chrono::seconds(20), "see the .log next to the data dir");
  }

  pid_t pid_ = -1;
  int stdout_ = -1;
  unsigned short port_ = 0;
};

}  // namespace pslam::server::testing
