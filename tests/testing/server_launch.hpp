#pragma once
// Starting the real pslam-server binary for tests and benchmarks: fork/exec on 127.0.0.1 with port
// 0, stdout on a pipe, stderr appended to a log. The server prints "listening on
// http://127.0.0.1:PORT" on stdout; the port is read from the pipe with a deadline.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace pslam::testing {

inline unsigned short ReadListeningPort(int stdout_fd, std::chrono::seconds timeout, const std::string& where_to_look) {
  std::string line;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{stdout_fd, POLLIN, 0};
    if (poll(&p, 1, 100) <= 0) continue;
    char c;
    if (read(stdout_fd, &c, 1) != 1) break;
    if (c != '\n') {
      line += c;
      continue;
    }
    const std::string prefix = "listening on http://127.0.0.1:";
    if (line.rfind(prefix, 0) == 0) return static_cast<unsigned short>(std::stoi(line.substr(prefix.size())));
    line.clear();
  }
  throw std::runtime_error("pslam-server did not report its port (" + where_to_look + ")");
}

struct LaunchedServer {
  pid_t pid = -1;
  int stdout_fd = -1;
  unsigned short port = 0;
};

// Runs 'binary' --listen 127.0.0.1:0 --data DATA_DIR 'extra_args' and waits for its port. The
// caller owns the returned child and pipe; on a timeout the child is killed and reaped, and the
// error names 'log_path'.
inline LaunchedServer LaunchServer(const std::string& binary, const std::filesystem::path& data_dir,
                                   const std::vector<std::string>& extra_args, const std::filesystem::path& log_path,
                                   std::chrono::seconds timeout) {
  int out[2];
  if (pipe(out) != 0) throw std::runtime_error("pipe failed");
  std::vector<std::string> args = {binary, "--listen", "127.0.0.1:0", "--data", data_dir.string()};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  LaunchedServer server;
  server.pid = fork();
  if (server.pid < 0) throw std::runtime_error("fork failed");
  if (server.pid == 0) {
    dup2(out[1], STDOUT_FILENO);
    const int err = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (err >= 0) dup2(err, STDERR_FILENO);
    close(out[0]);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(out[1]);
  server.stdout_fd = out[0];
  try {
    server.port = ReadListeningPort(server.stdout_fd, timeout, "see " + log_path.string());
  } catch (...) {
    kill(server.pid, SIGKILL);
    waitpid(server.pid, nullptr, 0);
    close(server.stdout_fd);
    throw;
  }
  return server;
}

}  // namespace pslam::testing
