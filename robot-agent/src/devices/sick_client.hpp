#pragma once
// Client side of a SICK LMS-200 (sick-lms200.md §8, Player's proven sequence): find the scanner's
// current rate with a polled-mode request, switch to the wanted transfer rate, read the measuring
// mode and units from the configuration, set the variant, start continuous output (mode 0x24), then
// decode 0xB0 telegrams on a reading thread.
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "devices/serial_port.hpp"
#include "devices/sick_protocol.hpp"

namespace pslam::agent {

struct SickClientOptions {
  int baud = 500000;                              // wanted transfer rate: 75 scans/s at 180 deg / 1 deg
  std::vector<int> probe_bauds = {9600, 38400, 500000};  // the scanner powers up at 9600
  double reply_timeout_s = 3.0;                   // mode switches (sicktoolbox: 3 s)
  double probe_timeout_s = 0.5;                   // per probed rate
  int scan_angle_deg = 180;
  int resolution_centideg = 100;
  // Scans are stamped on arrival of their STX, minus the time the mirror took to sweep them: ARIA
  // back-dates by one 75 Hz revolution.
  double scan_latency_s = 0.0133;
};

struct SickClientStats {
  std::size_t scans = 0;
  std::size_t bad_scans = 0;   // CRC-valid 0xB0 telegrams with an unexpected count or partial flag
  std::size_t other_telegrams = 0;
  sick::ParserStats parser;
};

struct SickScan {
  std::vector<float> ranges_m;  // NaN: no return
  double time = 0.0;
};

class SickClient {
 public:
  SickClient(std::string device, SickClientOptions options);
  ~SickClient();
  SickClient(const SickClient&) = delete;
  SickClient& operator=(const SickClient&) = delete;

  // Runs the start-up sequence; throws std::runtime_error with a clear message on failure.
  void Connect();
  // Geometry, valid after Connect().
  double angle_min_rad() const;
  double angle_increment_rad() const;
  std::size_t beams() const;
  double max_range_m() const { return max_range_m_; }

  // Starts the reading thread; 'on_scan' is called from it for every complete, valid scan.
  void Start(std::function<void(const SickScan&)> on_scan);
  // Stops streaming (mode 0x25) and joins the thread. Idempotent.
  void Shutdown();
  SickClientStats stats() const;

 private:
  std::optional<sick::Telegram> WaitReply(std::uint8_t reply_code, double timeout_s);
  bool SwitchMode(std::uint8_t mode, std::span<const std::uint8_t> extra = {});
  void Run();

  std::string device_;
  SickClientOptions options_;
  std::unique_ptr<SerialPort> port_;
  sick::TelegramParser parser_{true};
  std::uint8_t measuring_mode_ = 0;
  std::uint8_t unit_code_ = 1;
  double max_range_m_ = 8.191;
  std::function<void(const SickScan&)> on_scan_;
  mutable std::mutex mutex_;
  SickClientStats stats_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  bool shut_down_ = false;
};

}  // namespace pslam::agent
