#pragma once
// The robot's side of P2OS/ARCOS on a pseudo-terminal (p2os-arcos.md §11): waits for SYNC0/1/2,
// answers SYNC2 with name/class/subclass, streams SIPs after OPEN, starts with motors disabled,
// integrates VEL/RVEL into a 16-bit wrapping position, stops on its 2 s watchdog, drops packets
// with bad checksums. Fault injection: corrupt SIP checksums, SIPs split into slow pieces, line
// noise between packets.
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <numbers>
#include <thread>
#include <vector>

#include "devices/p2os_protocol.hpp"
#include "fakes/pty_pair.hpp"

namespace pslam::agent::testing {

struct FakePioneerOptions {
  std::string subclass = "p3dx-sh";
  double sip_period_s = 0.1;
  double watchdog_s = 2.0;
  std::uint16_t start_x = 0;  // raw XPOS at OPEN; near 0x7FFF to exercise wrap-around
  std::int16_t start_th = 0;
  bool open_at_start = false;  // as if a previous client left it open: SIPs flow before any SYNC
  int corrupt_every_nth_sip = 0;   // 0: never
  bool split_sips = false;         // write SIPs in 3-byte pieces 2 ms apart
  bool noise_between_packets = false;
};

class FakePioneer {
 public:
  explicit FakePioneer(FakePioneerOptions options = {}) : options_(options) {
    x_mm_ = options_.start_x;
    th_units_ = options_.start_th;
    open_ = options_.open_at_start;
    thread_ = std::thread([this] { Run(); });
  }
  ~FakePioneer() {
    stop_ = true;
    thread_.join();
  }
  const std::string& device() const { return pty_.slave_path(); }

  struct State {
    bool open = false, motors_enabled = false, sonar_on = true;
    int vel_mm_s = 0, rvel_deg_s = 0;
    int pulses = 0, vel_commands = 0, rvel_commands = 0, closes = 0, syncs = 0, bad_checksums = 0;
    int watchdog_trips = 0;
    double x_mm = 0, y_mm = 0, th_rad = 0;
  };
  State state() {
    const std::lock_guard<std::mutex> lock(mutex_);
    State s = state_;
    s.open = open_;
    s.x_mm = x_mm_;
    s.y_mm = y_mm_;
    s.th_rad = th_units_ * 2 * std::numbers::pi / 4096.0;
    return s;
  }
  void set_sips_enabled(bool on) { sips_enabled_ = on; }

 private:
  using Clock = std::chrono::steady_clock;

  void Send(const std::vector<std::uint8_t>& packet) {
    if (options_.noise_between_packets) {
      const std::uint8_t noise[] = {0xFA, 0x00, 0x13, 0xFB, 0x0D};  // includes a false header start
      pty_.Write(noise);
    }
    pty_.Write(packet);
  }

  void OnCommand(const p2os::DecodedCommand& c) {
    using namespace p2os;
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!open_) {
      // Wait state: only the handshake is answered; anything out of sequence restarts it.
      if (c.command == kSync0) {
        ++state_.syncs;
        sync_step_ = 1;
        Send(EncodeCommand(kSync0));
      } else if (c.command == kSync1 && sync_step_ == 1) {
        sync_step_ = 2;
        Send(EncodeCommand(kSync1));
      } else if (c.command == kSync2 && sync_step_ == 2) {
        sync_step_ = 3;
        Send(EncodePacket(EncodeSync2Reply({"Fake", "Pioneer", options_.subclass})));
      } else if (c.command == kOpen && sync_step_ == 3) {
        open_ = true;
        state_.motors_enabled = false;  // disabled at every new connection
        next_sip_ = Clock::now();
      } else {
        sync_step_ = 0;
      }
      return;
    }
    switch (c.command) {
      case kPulse: ++state_.pulses; break;
      case kClose:
        open_ = false;
        sync_step_ = 0;
        ++state_.closes;
        state_.vel_mm_s = state_.rvel_deg_s = 0;
        break;
      case kEnable: state_.motors_enabled = c.argument.value_or(0) != 0; break;
      case kSonar: state_.sonar_on = c.argument.value_or(1) != 0; break;
      case kVel: ++state_.vel_commands; state_.vel_mm_s = c.argument.value_or(0); break;
      case kRotVel: ++state_.rvel_commands; state_.rvel_deg_s = c.argument.value_or(0); break;
      case kStop: state_.vel_mm_s = state_.rvel_deg_s = 0; break;
      default: break;
    }
  }

  std::vector<std::uint8_t> MakeSip(double dt) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const bool moving = state_.motors_enabled && (state_.vel_mm_s != 0 || state_.rvel_deg_s != 0);
    const double th = th_units_ * 2 * std::numbers::pi / 4096.0;
    if (moving) {
      x_mm_ += state_.vel_mm_s * dt * std::cos(th);
      y_mm_ += state_.vel_mm_s * dt * std::sin(th);
      th_units_ += state_.rvel_deg_s * dt * 4096.0 / 360.0;
    }
    p2os::Sip sip;
    sip.type = moving ? p2os::kSipMoving : p2os::kSipStopped;
    // A 16-bit wrapping counter, as AMRISim keeps: its low 15 bits wrap cleanly.
    sip.x_pos = static_cast<std::uint16_t>(static_cast<std::int64_t>(std::lround(x_mm_)) & 0xFFFF);
    sip.y_pos = static_cast<std::uint16_t>(static_cast<std::int64_t>(std::lround(y_mm_)) & 0xFFFF);
    double wrapped = std::remainder(th_units_, 4096.0);  // +-2048, as AMRISim emits
    sip.th_pos = static_cast<std::int16_t>(std::lround(wrapped));
    const int wheel = moving ? state_.vel_mm_s : 0;
    sip.left_vel = sip.right_vel = static_cast<std::int16_t>(wheel);
    sip.battery_decivolts = 130;
    sip.flags = state_.motors_enabled ? 1 : 0;
    sip.battery_x10 = 130;
    sip.charge_state = 0;
    sip.rot_vel_decideg_s = static_cast<std::int16_t>(moving ? state_.rvel_deg_s * 10 : 0);
    sip.fault_flags = 0;
    auto packet = p2os::EncodePacket(p2os::EncodeSipPayload(sip));
    ++sips_sent_;
    if (options_.corrupt_every_nth_sip > 0 && sips_sent_ % options_.corrupt_every_nth_sip == 0) packet.back() ^= 0x5A;
    return packet;
  }

  void Run() {
    std::uint8_t buf[512];
    auto last_command = Clock::now();
    auto last_sip = Clock::now();
    while (!stop_) {
      const std::size_t n = pty_.Read(buf, 2);
      if (n > 0) parser_.Push({buf, n}, 0.0);
      while (auto packet = parser_.Next()) {
        last_command = Clock::now();
        if (auto c = p2os::DecodeCommand(packet->payload)) OnCommand(*c);
      }
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        state_.bad_checksums = static_cast<int>(parser_.stats().bad_checksum);
        const double silent = std::chrono::duration<double>(Clock::now() - last_command).count();
        if (open_ && silent > options_.watchdog_s && (state_.vel_mm_s != 0 || state_.rvel_deg_s != 0)) {
          state_.vel_mm_s = state_.rvel_deg_s = 0;  // the watchdog stops the robot
          ++state_.watchdog_trips;
        }
      }
      const auto now = Clock::now();
      if (open_ && sips_enabled_ && now >= next_sip_) {
        const double dt = std::chrono::duration<double>(now - last_sip).count();
        last_sip = now;
        next_sip_ = now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.sip_period_s));
        const auto sip = MakeSip(std::min(dt, 0.5));
        if (options_.split_sips) {
          for (std::size_t i = 0; i < sip.size(); i += 3) {
            pty_.Write({sip.data() + i, std::min<std::size_t>(3, sip.size() - i)});
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
          }
        } else {
          Send(sip);
        }
      }
    }
  }

  FakePioneerOptions options_;
  PtyPair pty_;
  p2os::PacketParser parser_;
  std::mutex mutex_;
  State state_;
  std::atomic<bool> open_{false};
  std::atomic<bool> sips_enabled_{true};
  int sync_step_ = 0;
  double x_mm_ = 0, y_mm_ = 0, th_units_ = 0;
  int sips_sent_ = 0;
  Clock::time_point next_sip_ = Clock::now();
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace pslam::agent::testing
