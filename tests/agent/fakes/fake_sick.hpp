#pragma once
// The scanner's side of the LMS-200 telegram protocol on a pseudo-terminal (sick-lms200.md §9):
// starts in polled mode at a nominal 9600 baud, answers valid telegrams with ACK + reply (NAK for a
// bad CRC), switches baud after replying, reports its configuration, accepts the variant, and in
// continuous mode streams 0xB0 scans at the configured cadence. Fault injection: corrupt CRCs,
// telegrams split into slow pieces, stray bytes (ACK/STX look-alikes) between telegrams.
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "devices/sick_protocol.hpp"
#include "fakes/pty_pair.hpp"

namespace pslam::agent::testing {

struct FakeSickOptions {
  int power_on_baud = 9600;
  double scan_rate_hz = 75.0;
  std::uint8_t measuring_mode = 0x00;  // 13-bit distances
  std::uint8_t unit_code = 1;          // mm
  int corrupt_every_nth_scan = 0;
  bool split_scans = false;
  bool noise_between_telegrams = false;
  // Range in mm of beam i (0..n-1) at scan k; default: a 2 m circle with a "no echo" beam 45.
  std::function<std::uint16_t(int beam, int scan)> range_mm;
};

class FakeSick {
 public:
  explicit FakeSick(FakeSickOptions options = {}) : options_(std::move(options)) {
    baud_ = options_.power_on_baud;
    thread_ = std::thread([this] { Run(); });
  }
  ~FakeSick() {
    stop_ = true;
    thread_.join();
  }
  const std::string& device() const { return pty_.slave_path(); }

  struct State {
    int baud = 0;
    bool streaming = false;
    int angle_deg = 180, resolution_cdeg = 100;
    int scans_sent = 0, naks_sent = 0, requests = 0;
  };
  State state() {
    const std::lock_guard<std::mutex> lock(mutex_);
    State s = state_;
    s.baud = baud_;
    s.streaming = streaming_;
    return s;
  }
  void set_streaming_paused(bool paused) { paused_ = paused; }

 private:
  using Clock = std::chrono::steady_clock;

  void Reply(std::uint8_t code, std::vector<std::uint8_t> data) {
    const std::uint8_t ack[] = {sick::kAck};
    pty_.Write(ack);
    pty_.Write(sick::EncodeReply(code, data, 0x10));  // status 0x10: class 0, as real scanners send
  }

  void OnRequest(const sick::Telegram& t) {
    using namespace sick;
    const std::lock_guard<std::mutex> lock(mutex_);
    ++state_.requests;
    switch (t.command) {
      case kSwitchMode: {
        const std::uint8_t mode = t.data.empty() ? 0xFF : t.data[0];
        Reply(kSwitchMode + kReplyOffset, {0x00});
        if (const auto baud = BaudOfMode(mode)) baud_ = *baud;  // after replying at the old rate
        if (mode == kModeContinuous) streaming_ = true, next_scan_ = Clock::now();
        if (mode == kModePolled) streaming_ = false;
        break;
      }
      case kReadConfig: {
        // 33 data bytes; index 6 (counting the reply code as 0) = measuring mode, 7 = unit.
        std::vector<std::uint8_t> config(33, 0);
        config[5] = options_.measuring_mode;
        config[6] = options_.unit_code;
        Reply(kReadConfig + kReplyOffset, config);
        break;
      }
      case kVariant: {
        if (t.data.size() == 4) {
          state_.angle_deg = t.data[0] | (t.data[1] << 8);
          state_.resolution_cdeg = t.data[2] | (t.data[3] << 8);
        }
        std::vector<std::uint8_t> data{1};
        data.insert(data.end(), t.data.begin(), t.data.end());
        Reply(kVariant + kReplyOffset, data);
        break;
      }
      case kStatus: Reply(kStatus + kReplyOffset, std::vector<std::uint8_t>(20, 0)); break;
      default: Reply(kNotAcknowledged, {}); break;
    }
  }

  std::vector<std::uint8_t> MakeScan() {
    const int n = state_.angle_deg * 100 / state_.resolution_cdeg + 1;
    std::vector<std::uint16_t> raw(n);
    for (int i = 0; i < n; ++i) {
      raw[i] = options_.range_mm ? options_.range_mm(i, state_.scans_sent) : (i == 45 ? 8191 : 2000);
      raw[i] |= static_cast<std::uint16_t>(0);  // no field flags
    }
    auto telegram = sick::EncodeReply(sick::kScanReply, sick::EncodeScanData(raw, options_.unit_code), 0x10);
    ++state_.scans_sent;
    if (options_.corrupt_every_nth_scan > 0 && state_.scans_sent % options_.corrupt_every_nth_scan == 0) {
      telegram[telegram.size() / 2] ^= 0x40;  // a flipped bit in the middle: the CRC catches it
    }
    return telegram;
  }

  void Run() {
    std::uint8_t buf[1024];
    while (!stop_) {
      const std::size_t n = pty_.Read(buf, 1);
      if (n > 0) {
        const std::size_t naks_before = parser_.stats().bad_crc;
        parser_.Push({buf, n}, 0.0);
        while (auto t = parser_.Next()) OnRequest(*t);
        if (parser_.stats().bad_crc > naks_before) {
          const std::uint8_t nak[] = {sick::kNak};
          pty_.Write(nak);
          const std::lock_guard<std::mutex> lock(mutex_);
          ++state_.naks_sent;
        }
      }
      std::vector<std::uint8_t> scan;
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (streaming_ && !paused_ && Clock::now() >= next_scan_) {
          next_scan_ += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options_.scan_rate_hz));
          scan = MakeScan();
        }
      }
      if (scan.empty()) continue;
      if (options_.noise_between_telegrams) {
        const std::uint8_t noise[] = {0x06, 0x02, 0x80, 0xFF, 0x15, 0x02};  // ACK, fake STX+address, NAK
        pty_.Write(noise);
      }
      if (options_.split_scans) {
        for (std::size_t i = 0; i < scan.size(); i += 97) {
          pty_.Write({scan.data() + i, std::min<std::size_t>(97, scan.size() - i)});
          std::this_thread::sleep_for(std::chrono::microseconds(300));
        }
      } else {
        pty_.Write(scan);
      }
    }
  }

  FakeSickOptions options_;
  PtyPair pty_;
  sick::TelegramParser parser_{false};
  std::mutex mutex_;
  State state_;
  int baud_ = 9600;
  bool streaming_ = false;
  std::atomic<bool> paused_{false};
  Clock::time_point next_scan_ = Clock::now();
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace pslam::agent::testing
