#pragma once
// A raw 8N1 serial line (termios): no echo, no CR/LF translation, no flow control, non-blocking
// reads with a timeout. Both protocols carry binary data in which 0x0D, 0x11 and 0x13 occur, so
// anything but cfmakeraw() would corrupt frames (p2os-arcos.md §1, sick-lms200.md §1).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace pslam::agent {

class SerialPort {
 public:
  // Throws std::runtime_error naming the device and the errno text on failure.
  SerialPort(const std::string& device, int baud);
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Changes the host-side line speed (after the device was told to switch). Throws on failure.
  void SetBaud(int baud);
  int baud() const { return baud_; }

  // Writes all of 'bytes' (a frame goes out as one burst, as the LMS-200 at 500 kbaud needs).
  // Throws on an I/O error.
  void Write(std::span<const std::uint8_t> bytes);
  // Reads what is available, waiting up to 'timeout_ms' for the first byte. Returns the number of
  // bytes read; 0 on timeout. Throws on an I/O error or hang-up.
  std::size_t Read(std::span<std::uint8_t> buffer, int timeout_ms);
  // Drops unread input and unsent output (after a baud change, before a handshake retry).
  void Flush();

  const std::string& device() const { return device_; }

 private:
  std::string device_;
  int fd_ = -1;
  int baud_ = 0;
};

}  // namespace pslam::agent
