#include "devices/sick_client.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/clock.hpp"
#include "common/log.hpp"

namespace pslam::agent {
namespace {

using namespace sick;

// Indexes into the 0xF4 configuration block counting the reply code as 0 (§6.3).
constexpr std::size_t kConfigMeasuringMode = 6;
constexpr std::size_t kConfigUnit = 7;

}  // namespace

SickClient::SickClient(std::string device, SickClientOptions options)
    : device_(std::move(device)), options_(std::move(options)) {}

SickClient::~SickClient() {
  try {
    Shutdown();
  } catch (const std::exception& e) {
    PSLAM_LOG(kWarning) << "laser shutdown: " << e.what();
  }
}

double SickClient::angle_min_rad() const { return -options_.scan_angle_deg / 2.0 * std::numbers::pi / 180.0; }
double SickClient::angle_increment_rad() const { return options_.resolution_centideg / 100.0 * std::numbers::pi / 180.0; }
std::size_t SickClient::beams() const {
  return static_cast<std::size_t>(options_.scan_angle_deg * 100 / options_.resolution_centideg + 1);
}

// Waits for the reply 'reply_code'; other telegrams (an 0xB0 still streaming) are passed over.
// A 0x92 "not acknowledged" ends the wait.
std::optional<Telegram> SickClient::WaitReply(std::uint8_t reply_code, double timeout_s) {
  const double deadline = AgentClock::Now() + timeout_s;
  std::uint8_t buf[1024];
  while (true) {
    while (auto t = parser_.Next()) {
      if (t->command == reply_code) return t;
      if (t->command == kNotAcknowledged) return std::nullopt;
    }
    const double left = deadline - AgentClock::Now();
    if (left <= 0) return std::nullopt;
    const std::size_t n = port_->Read(buf, std::max(1, static_cast<int>(left * 1000)));
    if (n > 0) parser_.Push({buf, n}, AgentClock::Now(), LineByteSeconds(port_->baud()));
  }
}

bool SickClient::SwitchMode(std::uint8_t mode, std::span<const std::uint8_t> extra) {
  std::vector<std::uint8_t> data{mode};
  data.insert(data.end(), extra.begin(), extra.end());
  port_->Write(EncodeRequest(kSwitchMode, data));
  const auto reply = WaitReply(kSwitchMode + kReplyOffset, options_.reply_timeout_s);
  return reply && !reply->data.empty() && reply->data[0] == 0x00;
}

void SickClient::Connect() {
  if (!BaudMode(options_.baud)) throw std::runtime_error("the LMS-200 cannot run at " + std::to_string(options_.baud) + " baud");
  if (!port_) port_ = std::make_unique<SerialPort>(device_, options_.probe_bauds.front());

  // 1. Which rate is the scanner at? A polled-mode request answers with 0xA0 (also stops a stream).
  int found = 0;
  std::vector<int> rates = options_.probe_bauds;
  if (std::find(rates.begin(), rates.end(), options_.baud) == rates.end()) rates.push_back(options_.baud);
  for (int rate : rates) {
    port_->SetBaud(rate);
    port_->Flush();
    parser_.Clear();
    const std::uint8_t polled[] = {kModePolled};
    port_->Write(EncodeRequest(kSwitchMode, polled));
    if (const auto reply = WaitReply(kSwitchMode + kReplyOffset, options_.probe_timeout_s)) {
      found = rate;
      break;
    }
  }
  if (found == 0) {
    throw std::runtime_error("no SICK LMS-200 answered on " + device_ +
                             " at any probed baud rate (powered? booted? it needs ~35 s after power-on)");
  }
  // 2. Switch to the transfer rate: the scanner answers at the old rate, then changes.
  if (found != options_.baud) {
    if (!SwitchMode(*BaudMode(options_.baud))) {
      throw std::runtime_error("the LMS-200 on " + device_ + " refused to switch to " + std::to_string(options_.baud) + " baud");
    }
    port_->SetBaud(options_.baud);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    port_->Flush();
    parser_.Clear();
    if (!SwitchMode(kModePolled)) {
      throw std::runtime_error("the LMS-200 on " + device_ + " went silent after switching to " +
                               std::to_string(options_.baud) + " baud");
    }
  }
  // 3. Measuring mode and units decide which bits of a value are the distance (§6.2).
  port_->Write(EncodeRequest(kReadConfig));
  if (const auto config = WaitReply(kReadConfig + kReplyOffset, options_.reply_timeout_s);
      config && config->data.size() >= kConfigUnit) {
    measuring_mode_ = config->data[kConfigMeasuringMode - 1];
    unit_code_ = config->data[kConfigUnit - 1];
  } else {
    PSLAM_LOG(kWarning) << "LMS-200 configuration not readable; assuming the factory measuring mode 0 (13-bit ranges)";
  }
  max_range_m_ = RangeFormatFor(measuring_mode_, unit_code_).max_range_m;
  // 4. Variant (scan angle, resolution).
  const std::uint8_t variant[] = {static_cast<std::uint8_t>(options_.scan_angle_deg & 0xFF),
                                  static_cast<std::uint8_t>(options_.scan_angle_deg >> 8),
                                  static_cast<std::uint8_t>(options_.resolution_centideg & 0xFF),
                                  static_cast<std::uint8_t>(options_.resolution_centideg >> 8)};
  port_->Write(EncodeRequest(kVariant, variant));
  const auto variant_reply = WaitReply(kVariant + kReplyOffset, options_.reply_timeout_s);
  if (!variant_reply || variant_reply->data.empty() || variant_reply->data[0] == 0) {
    throw std::runtime_error("the LMS-200 on " + device_ + " rejected the variant " +
                             std::to_string(options_.scan_angle_deg) + " deg / " +
                             std::to_string(options_.resolution_centideg / 100.0) + " deg");
  }
  // 5. Continuous output of all values.
  if (!SwitchMode(kModeContinuous)) throw std::runtime_error("the LMS-200 on " + device_ + " refused continuous output");
  PSLAM_LOG(kInfo) << "LMS-200 on " << device_ << " streaming at " << options_.baud << " baud, " << beams()
                   << " beams, measuring mode " << int(measuring_mode_) << ", max range " << max_range_m_ << " m";
}

void SickClient::Start(std::function<void(const SickScan&)> on_scan) {
  on_scan_ = std::move(on_scan);
  thread_ = std::thread([this] { Run(); });
}

void SickClient::Run() {
  std::uint8_t buf[4096];
  const std::size_t expected = beams();
  while (!stop_) {
    try {
      const std::size_t n = port_->Read(buf, 20);
      if (n > 0) parser_.Push({buf, n}, AgentClock::Now(), LineByteSeconds(port_->baud()));
      while (auto t = parser_.Next()) {
        if (t->command != kScanReply) {
          const std::lock_guard<std::mutex> lock(mutex_);
          ++stats_.other_telegrams;
          continue;
        }
        auto scan = DecodeScan(*t, measuring_mode_);
        if (!scan || scan->partial || scan->ranges_m.size() != expected) {
          const std::lock_guard<std::mutex> lock(mutex_);
          ++stats_.bad_scans;
          continue;
        }
        {
          const std::lock_guard<std::mutex> lock(mutex_);
          ++stats_.scans;
        }
        if (on_scan_) on_scan_(SickScan{std::move(scan->ranges_m), t->time - options_.scan_latency_s});
      }
    } catch (const std::exception& e) {
      PSLAM_LOG(kError) << "laser link: " << e.what();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    const std::lock_guard<std::mutex> lock(mutex_);
    stats_.parser = parser_.stats();
  }
}

void SickClient::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (port_) {
    const std::uint8_t polled[] = {kModePolled};
    port_->Write(EncodeRequest(kSwitchMode, polled));
  }
}

SickClientStats SickClient::stats() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

}  // namespace pslam::agent
