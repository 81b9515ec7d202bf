#pragma once
// The agent loop: read the source -> spool every message -> let the link stream it; and, beside it,
// drive: target path from the server -> pure pursuit (core's PathFollower) -> safety -> wheels.
//
// The loop never waits on the network: the link runs on its own thread and only reads the spool.
// A full spool refuses new messages (counted and reported) when the source is live; a log replay
// waits for room instead.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "agent_options.hpp"
#include "drive/safety.hpp"
#include "drive/stall_recovery.hpp"
#include "link/messages.hpp"
#include "link/server_link.hpp"
#include "link/spool.hpp"
#include "pslam/explore/look_around.hpp"
#include "pslam/explore/path_follower.hpp"
#include "sources/scan_source.hpp"

namespace pslam::agent {

// Exit codes of Run().
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitRefused = 3;         // the server refused the token
inline constexpr int kExitSessionRefused = 4;  // the server refused the hello, or the session failed

struct AgentStats {
  std::uint64_t scans = 0;
  std::uint64_t odometry = 0;
  std::uint64_t dropped_spool_full = 0;
  std::uint64_t targets = 0;
  StopReason stop_reason = StopReason::kNone;
  int stalls = 0;  // times the wheels stalled against something and the robot backed off
};

class Agent {
 public:
  // 'source' is connected already (its laser geometry goes into `hello`).
  Agent(AgentOptions options, std::unique_ptr<ScanSource> source);
  ~Agent();

  // Runs until 'stop' is set, the server refuses the agent for good, or a finite source is finished
  // and everything it produced is acknowledged (then the session is closed). Returns an exit code.
  int Run(const std::atomic<bool>& stop);

  AgentStats stats() const { return stats_; }
  LinkStatus link_status() const { return link_->status(); }
  SpoolStats spool_stats() const { return spool_->stats(); }

 private:
  void Enqueue(const OdomMessage& odom);
  void Enqueue(const ScanMessage& scan);
  void Append(const std::vector<std::uint8_t>& payload, const std::atomic<bool>& stop);
  void ContinueReplay();
  void CloseFinishedSession();
  void DriveTick(double now);
  void LogStatus(double now);
  // options_.close_on_exit: waits for the last acknowledgements, then closes the session on the server.
  void CloseSessionOnExit();
  // options_.close_on_exit: closes the session a previous run left open (killed, or the server was
  // unreachable when it stopped) and drops what that run did not deliver.
  void CloseLeftoverSession();

  AgentOptions options_;
  std::unique_ptr<ScanSource> source_;
  std::unique_ptr<Spool> spool_;
  std::unique_ptr<ServerLink> link_;
  ServerLinkOptions link_options_;
  PathFollower follower_;
  bool path_active_ = false;
  LookAround look_around_;  // a target's turn in place, before its path is followed
  std::optional<std::array<double, 2>> logged_target_;  // the target last named in the log
  SafetyMonitor safety_;
  StallRecovery stall_;
  AgentStats stats_;
  const std::atomic<bool>* stop_ = nullptr;
  std::optional<OdometryReading> latest_odometry_;
  double last_drive_tick_ = 0.0;
  double last_status_ = 0.0;
  double spool_full_since_ = -1.0;
  double last_spool_full_report_ = 0.0;
  VelocityCommand last_command_;
};

}  // namespace pslam::agent
