#pragma once
// pslam-server started with port 0 prints "listening on http://127.0.0.1:PORT" on stdout: tests and
// benchmarks read the port from the pipe, with a deadline.
#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <string>

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

}  // namespace pslam::testing
