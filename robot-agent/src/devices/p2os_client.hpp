#pragma once
// Client side of the P2OS/ARCOS link to a Pioneer 3-DX (p2os-arcos.md §4): SYNC0/1/2 handshake with
// auto-baud and recovery, OPEN, ENABLE, optional HOSTBAUD switch, then a reading thread that decodes
// SIPs into odometry and keeps the robot's watchdog fed with velocity commands or PULSEs.
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "devices/p2os_protocol.hpp"
#include "devices/serial_port.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam::agent {

struct P2osClientOptions {
  int baud = 9600;  // power-on rate; others are probed in Player's order if it does not answer
  std::vector<int> probe_bauds = {9600, 38400, 19200, 115200, 57600};
  int switch_to_baud = 0;                  // 0: stay; else HOSTBAUD to this rate after OPEN (ARIA uses 38400)
  double reply_timeout_s = 0.3;            // per SYNC step (Player 200 ms, ARIA up to 1 s)
  int sync_attempts_per_baud = 4;
  double keepalive_period_s = 0.4;         // PULSE if nothing was sent for this long (watchdog: 2 s)
  double velocity_repeat_s = 0.3;          // re-send VEL/RVEL: the protocol is unacknowledged
  double command_spacing_s = 0.005;        // the manual's 3-5 ms between client commands
  double sip_timeout_s = 1.0;              // no valid SIP for this long is a fault (§4.3)
  double reconnect_after_s = 3.0;          // then the handshake is redone from SYNC0
  bool enable_motors = true;
  bool disable_sonar = true;               // a laser-only agent shortens SIPs (§4.2 step 7)
};

struct P2osClientStats {
  std::size_t sips = 0;
  std::size_t other_packets = 0;
  p2os::ParserStats parser;
  std::size_t reconnects = 0;
  bool fault = false;  // currently no SIPs within sip_timeout_s
};

class P2osClient {
 public:
  P2osClient(std::string device, P2osClientOptions options);
  ~P2osClient();
  P2osClient(const P2osClient&) = delete;
  P2osClient& operator=(const P2osClient&) = delete;

  // Handshake, OPEN, ENABLE. Throws std::runtime_error with a clear message if the robot does not
  // answer at any baud rate.
  void Connect();
  const p2os::RobotIdentity& identity() const { return identity_; }
  const p2os::RobotParams& params() const { return params_; }

  // Starts the reading thread; 'on_odometry' is called from it for every valid SIP, stamped with
  // the arrival time of the SIP's first byte.
  void Start(std::function<void(const OdometryReading&)> on_odometry);
  // Thread-safe. Sent as VEL (mm/s) and RVEL (deg/s, + counter-clockwise) at the next free slot.
  void SetVelocity(double v_m_s, double w_rad_s);
  // Stops the robot (STOP, ENABLE 0, CLOSE, as Player/ARIA do) and joins the thread. Idempotent.
  void Shutdown();

  P2osClientStats stats() const;

 private:
  std::optional<p2os::Packet> WaitPacket(double timeout_s);
  bool TrySync();
  void Send(const std::vector<std::uint8_t>& packet);
  void Run();
  void ServiceCommands(double now);

  std::string device_;
  P2osClientOptions options_;
  std::unique_ptr<SerialPort> port_;
  p2os::PacketParser parser_;
  p2os::RobotIdentity identity_;
  p2os::RobotParams params_;
  std::optional<p2os::OdometryIntegrator> odometry_;
  std::function<void(const OdometryReading&)> on_odometry_;

  mutable std::mutex mutex_;  // guards the commanded velocity and the stats
  int commanded_vel_mm_s_ = 0;
  int commanded_rvel_deg_s_ = 0;
  bool velocity_commanded_ = false;  // PULSE keeps the watchdog fed until the first command
  P2osClientStats stats_;

  // Owned by the reading thread.
  int sent_vel_ = 0, sent_rvel_ = 0;
  bool sent_any_velocity_ = false;
  double last_send_ = 0.0, last_velocity_send_ = 0.0, last_sip_ = 0.0;
  bool rvel_pending_ = false;

  std::atomic<bool> stop_{false};
  std::thread thread_;
  bool shut_down_ = false;
};

}  // namespace pslam::agent
