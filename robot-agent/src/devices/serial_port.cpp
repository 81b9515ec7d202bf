#include "devices/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace pslam::agent {
namespace {

speed_t SpeedConstant(int baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    // Linux defines B500000; FTDI and CP210x USB-RS422 adapters accept it directly. Adapters that
    // need the old ASYNC_SPD_CUST divisor trick (sick-lms200.md §1) are not supported.
    case 500000: return B500000;
    default: throw std::runtime_error("unsupported baud rate " + std::to_string(baud));
  }
}

std::runtime_error SystemError(const std::string& what, const std::string& device) {
  return std::runtime_error(what + " " + device + ": " + std::strerror(errno));
}

}  // namespace

SerialPort::SerialPort(const std::string& device, int baud) : device_(device) {
  fd_ = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw SystemError("cannot open serial port", device);
  try {
    SetBaud(baud);
  } catch (...) {
    ::close(fd_);
    throw;
  }
}

SerialPort::~SerialPort() {
  if (fd_ >= 0) ::close(fd_);
}

void SerialPort::SetBaud(int baud) {
  termios tio{};
  if (::tcgetattr(fd_, &tio) != 0) throw SystemError("tcgetattr", device_);
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;  // ignore modem lines: a Pioneer's port has no carrier detect
  tio.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS);
  tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  const speed_t speed = SpeedConstant(baud);
  ::cfsetispeed(&tio, speed);
  ::cfsetospeed(&tio, speed);
  if (::tcsetattr(fd_, TCSANOW, &tio) != 0) throw SystemError("tcsetattr", device_);
  baud_ = baud;
}

void SerialPort::Write(std::span<const std::uint8_t> bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, 1000) <= 0) throw std::runtime_error("serial write timed out on " + device_);
      continue;
    }
    throw SystemError("write to", device_);
  }
}

std::size_t SerialPort::Read(std::span<std::uint8_t> buffer, int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return 0;
    throw SystemError("poll", device_);
  }
  if (ready == 0) return 0;
  const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
  if (n > 0) return static_cast<std::size_t>(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  if (n == 0 || (p.revents & POLLHUP)) throw std::runtime_error("serial device hung up: " + device_);
  throw SystemError("read from", device_);
}

void SerialPort::Flush() { ::tcflush(fd_, TCIOFLUSH); }

}  // namespace pslam::agent
