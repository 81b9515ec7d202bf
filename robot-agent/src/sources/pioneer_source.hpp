#pragma once
// The real robot: a Pioneer 3-DX over P2OS/ARCOS for odometry and driving, and a SICK LMS-200 for
// scans, each on its own serial port and reading thread. Scans are stamped on arrival; their
// odometry is interpolated from the SIPs around them (OdometryInterpolator).
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "devices/p2os_client.hpp"
#include "devices/sick_client.hpp"
#include "sources/odometry_interpolator.hpp"
#include "sources/scan_source.hpp"

namespace pslam::agent {

struct PioneerSourceOptions {
  std::string robot_device;  // e.g. /dev/ttyS0
  std::string laser_device;  // e.g. /dev/ttyUSB0
  P2osClientOptions robot;
  SickClientOptions laser;
  Pose2D laser_offset{0.018, 0.0, 0.0};  // ARIA p3dx(-sh).p: LaserX 18 mm
  std::size_t max_queued_events = 1024;  // if the agent stalls, the oldest events are dropped (counted)
};

class PioneerSource : public ScanSource {
 public:
  // Connects both devices; throws std::runtime_error with a clear message if either is silent.
  explicit PioneerSource(PioneerSourceOptions options);
  ~PioneerSource() override;

  std::string description() const override;
  LaserDescription laser() const override;
  std::optional<SourceEvent> Next(double timeout_s) override;
  bool can_drive() const override { return true; }
  void Drive(const VelocityCommand& command) override { robot_->SetVelocity(command.v, command.w); }
  std::string StatsLine() const override;
  void Shutdown() override;

 private:
  void Push(SourceEvent event);

  PioneerSourceOptions options_;
  std::unique_ptr<P2osClient> robot_;
  std::unique_ptr<SickClient> laser_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<SourceEvent> queue_;  // from the device threads, in arrival order
  std::size_t dropped_ = 0;
  OdometryInterpolator interpolator_;
  std::deque<SourceEvent> out_;    // odometry passed through, scans once interpolated
};

}  // namespace pslam::agent
