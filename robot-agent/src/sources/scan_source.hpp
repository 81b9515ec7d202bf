#pragma once
// Where scans and odometry come from: the simulator, a recorded log, or the real robot. The agent
// loop is the same for all three; only a source knows how to wait for data and whether it can
// drive.
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "common/laser_description.hpp"
#include "drive/velocity_command.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam::agent {

// Scans carry their time stamp and the robot's raw odometry interpolated to it.
using SourceEvent = std::variant<OdometryReading, LaserScan>;

class ScanSource {
 public:
  virtual ~ScanSource() = default;

  virtual std::string description() const = 0;
  virtual LaserDescription laser() const = 0;

  // The next event in time order, waiting up to 'timeout_s'; nullopt on timeout or at the end.
  virtual std::optional<SourceEvent> Next(double timeout_s) = 0;
  // True once a finite source (a log) has delivered everything.
  virtual bool finished() const { return false; }
  // A live sensor cannot pause; a replay can wait for room in a full spool instead of losing data.
  virtual bool can_wait() const { return false; }
  // A replay names what it replays (its events are the same every run); live sources return "".
  virtual std::string replay_name() const { return {}; }
  // Skips the first 'events' events without pacing (a replay continued after a restart); returns
  // how many there were.
  virtual std::uint64_t Skip(std::uint64_t /*events*/) { return 0; }

  virtual bool can_drive() const = 0;
  // Executes a velocity command (no-op for sources that cannot drive).
  virtual void Drive(const VelocityCommand& command) = 0;

  // One line of source-specific counters for the periodic status log (frame errors and such).
  virtual std::string StatsLine() const { return {}; }
  // Stops the robot and releases the devices. Idempotent.
  virtual void Shutdown() {}
};

}  // namespace pslam::agent
