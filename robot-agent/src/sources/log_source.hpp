#pragma once
// Replays a recorded CARMEN log (.clf/.log, gzip too) through the agent as if it were the robot:
// odometry and scans in time order with their original time stamps, paced at 'rate' times real
// time (or as fast as the link takes them). Scans whose line carries no odometry pose get it
// interpolated from the ODOM records around them.
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "pslam/io/carmen_reader.hpp"
#include "sources/odometry_interpolator.hpp"
#include "sources/scan_source.hpp"

namespace pslam::agent {

struct LogSourceOptions {
  std::string path;
  double rate = 1.0;  // times real time; 0 = as fast as possible
  std::size_t max_scans = 0;  // stop after this many scans (0: the whole log)
};

class LogSource : public ScanSource {
 public:
  // Throws std::runtime_error if the log cannot be opened or holds no scan.
  explicit LogSource(LogSourceOptions options);

  std::string description() const override;
  LaserDescription laser() const override { return laser_; }
  std::optional<SourceEvent> Next(double timeout_s) override;
  bool finished() const override { return finished_; }
  bool can_wait() const override { return true; }
  std::string replay_name() const override { return options_.path; }
  std::uint64_t Skip(std::uint64_t events) override;
  bool can_drive() const override { return false; }
  void Drive(const VelocityCommand&) override {}
  std::string StatsLine() const override;

 private:
  std::optional<SourceEvent> ReadEvent();  // next event from the log, odometry resolved
  std::optional<SourceEvent> Take();       // the next event, counted against max_scans; no pacing
  bool FillLookahead();                     // false (and finished) when the log has no event left

  LogSourceOptions options_;
  CarmenReader reader_;
  OdometryInterpolator interpolator_{1e9};  // a log has all the odometry: never hold
  std::deque<SourceEvent> lookahead_;       // events read while finding the first scan
  LaserDescription laser_;
  std::optional<double> first_log_time_;
  double wall_start_ = 0.0;
  std::size_t scans_ = 0;
  bool reader_done_ = false;
  bool finished_ = false;
};

}  // namespace pslam::agent
