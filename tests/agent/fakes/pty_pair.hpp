#pragma once
// A pseudo-terminal pair for device simulators: the simulator owns the master side, the agent opens
// the slave path as if it were /dev/ttyS0. Both sides are raw (binary-clean), as a real serial
// line is.
#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

namespace pslam::agent::testing {

class PtyPair {
 public:
  PtyPair() {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0) {
      throw std::runtime_error(std::string("posix_openpt: ") + std::strerror(errno));
    }
    char name[128];
    if (::ptsname_r(master_, name, sizeof name) != 0) throw std::runtime_error("ptsname_r failed");
    slave_path_ = name;
    termios tio{};
    ::tcgetattr(master_, &tio);
    ::cfmakeraw(&tio);
    ::tcsetattr(master_, TCSANOW, &tio);
    // Keep a slave descriptor open ourselves: without one, the master reads EIO whenever the
    // agent closes and reopens the port, and the line's raw settings would be lost.
    slave_keepalive_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (slave_keepalive_ >= 0) {
      ::tcgetattr(slave_keepalive_, &tio);
      ::cfmakeraw(&tio);
      ::tcsetattr(slave_keepalive_, TCSANOW, &tio);
    }
  }
  ~PtyPair() {
    if (slave_keepalive_ >= 0) ::close(slave_keepalive_);
    if (master_ >= 0) ::close(master_);
  }
  PtyPair(const PtyPair&) = delete;
  PtyPair& operator=(const PtyPair&) = delete;

  const std::string& slave_path() const { return slave_path_; }

  // Reads what is available within 'timeout_ms'; 0 on timeout.
  std::size_t Read(std::span<std::uint8_t> buffer, int timeout_ms) {
    pollfd p{master_, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return 0;
    const ssize_t n = ::read(master_, buffer.data(), buffer.size());
    return n > 0 ? static_cast<std::size_t>(n) : 0;
  }
  void Write(std::span<const std::uint8_t> bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(master_, bytes.data() + done, bytes.size() - done);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n <= 0) return;
      done += static_cast<std::size_t>(n);
    }
  }

 private:
  int master_ = -1;
  int slave_keepalive_ = -1;
  std::string slave_path_;
};

}  // namespace pslam::agent::testing
