#include "devices/p2os_client.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/clock.hpp"
#include "common/log.hpp"

namespace pslam::agent {
namespace {

using namespace p2os;

void SleepSeconds(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

std::optional<int> HostBaudCode(int baud) {
  switch (baud) {
    case 9600: return 0;
    case 19200: return 1;
    case 38400: return 2;
    case 57600: return 3;
    case 115200: return 4;
    default: return std::nullopt;
  }
}

bool IsEcho(const Packet& p, std::uint8_t sync) { return p.payload.size() == 1 && p.payload[0] == sync; }

}  // namespace

P2osClient::P2osClient(std::string device, P2osClientOptions options)
    : device_(std::move(device)), options_(std::move(options)) {}

P2osClient::~P2osClient() {
  try {
    Shutdown();
  } catch (const std::exception& e) {
    PSLAM_LOG(kWarning) << "pioneer shutdown: " << e.what();
  }
}

void P2osClient::Send(const std::vector<std::uint8_t>& packet) {
  port_->Write(packet);
  last_send_ = AgentClock::Now();
}

std::optional<Packet> P2osClient::WaitPacket(double timeout_s) {
  const double deadline = AgentClock::Now() + timeout_s;
  std::uint8_t buf[256];
  while (true) {
    if (auto p = parser_.Next()) return p;
    const double left = deadline - AgentClock::Now();
    if (left <= 0) return std::nullopt;
    const std::size_t n = port_->Read(buf, std::max(1, static_cast<int>(left * 1000)));
    if (n > 0) parser_.Push({buf, n}, AgentClock::Now(), LineByteSeconds(port_->baud()));
  }
}

// One SYNC0/1/2 round at the current baud (§4.1). Restarts from SYNC0 on anything unexpected; a SIP
// means a previous client left the robot open, so it is closed first (ARIA and Player do this).
bool P2osClient::TrySync() {
  for (int attempt = 0; attempt < options_.sync_attempts_per_baud; ++attempt) {
    Send(EncodeCommand(kSync0));
    auto reply = WaitPacket(options_.reply_timeout_s);
    if (!reply) continue;
    if (!reply->payload.empty() && IsStandardSip(reply->payload[0])) {
      PSLAM_LOG(kInfo) << "pioneer on " << device_ << " is still open from a previous client: closing it";
      Send(EncodeCommand(kClose));
      SleepSeconds(0.2);
      port_->Flush();
      parser_.DiscardPartial();
      continue;
    }
    if (!IsEcho(*reply, kSync0)) continue;
    Send(EncodeCommand(kSync1));
    reply = WaitPacket(options_.reply_timeout_s);
    if (!reply || !IsEcho(*reply, kSync1)) continue;
    Send(EncodeCommand(kSync2));
    reply = WaitPacket(options_.reply_timeout_s);
    if (!reply) continue;
    if (auto id = ParseSync2Reply(reply->payload)) {
      identity_ = *id;
      return true;
    }
  }
  return false;
}

void P2osClient::Connect() {
  if (!port_) port_ = std::make_unique<SerialPort>(device_, options_.baud);
  std::vector<int> bauds{options_.baud};
  for (int b : options_.probe_bauds) {
    if (std::find(bauds.begin(), bauds.end(), b) == bauds.end()) bauds.push_back(b);
  }
  bool synced = false;
  for (int baud : bauds) {
    port_->SetBaud(baud);
    port_->Flush();
    parser_.DiscardPartial();
    if ((synced = TrySync())) break;
  }
  if (!synced) {
    throw std::runtime_error("no Pioneer answered the P2OS handshake on " + device_ +
                             " at any of the probed baud rates (is the robot on, the cable in the HOST port?)");
  }
  params_ = ParamsForSubclass(identity_.subclass);
  PSLAM_LOG(kInfo) << "pioneer '" << identity_.name << "' class " << identity_.robot_class << " subclass "
                   << identity_.subclass << " on " << device_ << " at " << port_->baud()
                   << " baud (DistConvFactor " << params_.dist_conv_mm << ")";

  Send(EncodeCommand(kOpen));
  SleepSeconds(options_.command_spacing_s);
  if (options_.switch_to_baud != 0 && options_.switch_to_baud != port_->baud()) {
    // ARIA's switch: HOSTBAUD, ~10 ms, change our side, PULSE, expect any packet within 900 ms.
    if (const auto code = HostBaudCode(options_.switch_to_baud)) {
      const int old_baud = port_->baud();
      Send(EncodeCommand(kHostBaud, *code));
      SleepSeconds(0.01);
      port_->SetBaud(options_.switch_to_baud);
      port_->Flush();
      parser_.DiscardPartial();
      Send(EncodeCommand(kPulse));
      if (!WaitPacket(0.9)) {
        PSLAM_LOG(kWarning) << "pioneer did not answer at " << options_.switch_to_baud << " baud; staying at "
                            << old_baud;
        port_->SetBaud(old_baud);
      }
    }
  }
  if (options_.disable_sonar) {
    SleepSeconds(options_.command_spacing_s);
    Send(EncodeCommand(kSonar, 0));
  }
  if (options_.enable_motors) {
    // Motors are disabled at every new connection (§4.2 step 6).
    SleepSeconds(options_.command_spacing_s);
    Send(EncodeCommand(kEnable, 1));
  }
  if (!odometry_) odometry_.emplace(params_);
  last_sip_ = AgentClock::Now();
}

void P2osClient::Start(std::function<void(const OdometryReading&)> on_odometry) {
  on_odometry_ = std::move(on_odometry);
  thread_ = std::thread([this] { Run(); });
}

void P2osClient::SetVelocity(double v_m_s, double w_rad_s) {
  const std::lock_guard<std::mutex> lock(mutex_);
  commanded_vel_mm_s_ = static_cast<int>(std::lround(v_m_s * 1000.0));
  commanded_rvel_deg_s_ = static_cast<int>(std::lround(w_rad_s * 180.0 / std::numbers::pi));
  velocity_commanded_ = true;
}

// At most one packet per call, and never closer than command_spacing_s to the previous one.
void P2osClient::ServiceCommands(double now) {
  if (now - last_send_ < options_.command_spacing_s) return;
  int vel = 0, rvel = 0;
  bool commanded = false;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    vel = commanded_vel_mm_s_;
    rvel = commanded_rvel_deg_s_;
    commanded = velocity_commanded_;
  }
  if (commanded) {
    if (rvel_pending_) {
      Send(EncodeCommand(kRotVel, sent_rvel_));
      rvel_pending_ = false;
      return;
    }
    if (!sent_any_velocity_ || vel != sent_vel_ || rvel != sent_rvel_ ||
        now - last_velocity_send_ >= options_.velocity_repeat_s) {
      Send(EncodeCommand(kVel, vel));
      sent_vel_ = vel;
      sent_rvel_ = rvel;
      sent_any_velocity_ = true;
      rvel_pending_ = true;
      last_velocity_send_ = now;
      return;
    }
  }
  if (now - last_send_ >= options_.keepalive_period_s) Send(EncodeCommand(kPulse));
}

void P2osClient::Run() {
  std::uint8_t buf[512];
  double last_byte = AgentClock::Now();
  double last_reconnect_try = 0.0;
  while (!stop_) {
    double now = AgentClock::Now();
    try {
      ServiceCommands(now);
      const std::size_t n = port_->Read(buf, 10);
      now = AgentClock::Now();
      if (n > 0) {
        parser_.Push({buf, n}, now, LineByteSeconds(port_->baud()));
        last_byte = now;
      } else if (parser_.has_partial() && now - last_byte > 0.1) {
        parser_.DiscardPartial();  // ARIA: give up on a partial packet after 100 ms of silence
      }
      while (auto packet = parser_.Next()) {
        if (auto sip = DecodeSip(packet->payload)) {
          const OdometryReading odom = odometry_->Update(*sip, packet->time);
          last_sip_ = now;
          {
            const std::lock_guard<std::mutex> lock(mutex_);
            ++stats_.sips;
            if (stats_.fault) PSLAM_LOG(kInfo) << "pioneer SIPs are back";
            stats_.fault = false;
          }
          if (on_odometry_) on_odometry_(odom);
        } else {
          if (!packet->payload.empty() && packet->payload[0] >= 0xFE) {
            PSLAM_LOG(kWarning) << "pioneer microcontroller reset notice: reconnecting";
            last_sip_ = now - options_.reconnect_after_s;
          }
          const std::lock_guard<std::mutex> lock(mutex_);
          ++stats_.other_packets;
        }
      }
      if (now - last_sip_ > options_.sip_timeout_s) {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (!stats_.fault) PSLAM_LOG(kError) << "no SIP from the pioneer for " << options_.sip_timeout_s << " s";
        stats_.fault = true;
      }
      if (now - last_sip_ > options_.reconnect_after_s && now - last_reconnect_try > options_.reconnect_after_s) {
        last_reconnect_try = now;
        PSLAM_LOG(kWarning) << "redoing the P2OS handshake on " << device_;
        Connect();
        sent_any_velocity_ = false;  // the robot forgot our velocity with the connection
        const std::lock_guard<std::mutex> lock(mutex_);
        ++stats_.reconnects;
      }
    } catch (const std::exception& e) {
      PSLAM_LOG(kError) << "pioneer link: " << e.what();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stats_.parser = parser_.stats();
    }
  }
}

void P2osClient::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (!port_) return;
  // Player: STOP then CLOSE; ARIA: ENABLE 0 then CLOSE. Do both, paced.
  for (const auto& packet : {EncodeCommand(kStop), EncodeCommand(kEnable, 0), EncodeCommand(kClose)}) {
    port_->Write(packet);
    SleepSeconds(0.02);
  }
}

P2osClientStats P2osClient::stats() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

}  // namespace pslam::agent
