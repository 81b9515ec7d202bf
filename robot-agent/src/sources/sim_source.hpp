#pragma once
// The simulated Pioneer 3-DX with its LMS-200 (core/pslam/sim), run against the wall clock at
// 'rate' times real time, or as fast as the agent takes events. The same drive code as on the
// robot commands it: Drive() sets the simulator's velocity command.
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "pslam/sim/simulator.hpp"
#include "sources/scan_source.hpp"

namespace pslam::agent {

struct SimSourceOptions {
  // "" or a shipped world name ("maze", "office", "irregular"): generated in memory, no file needed;
  // anything else is a map_server YAML (its "# start:" line gives the start pose).
  std::string world;
  double rate = 1.0;  // times real time; 0 = as fast as possible
  double scan_rate_hz = 10.0;
  double odometry_rate_hz = 10.0;
  std::uint64_t seed = 1;
};

class SimSource : public ScanSource {
 public:
  // Throws std::runtime_error for an unreadable world or a blocked start pose.
  explicit SimSource(SimSourceOptions options);

  std::string description() const override { return description_; }
  LaserDescription laser() const override;
  std::optional<SourceEvent> Next(double timeout_s) override;
  bool can_drive() const override { return true; }
  void Drive(const VelocityCommand& command) override;
  std::string StatsLine() const override;

  // Visible for testing.
  const Simulator& simulator() const { return *simulator_; }

 private:
  SimSourceOptions options_;
  std::string description_;
  std::unique_ptr<Simulator> simulator_;
  std::deque<SourceEvent> pending_;
  double sim_start_ = 0.0;
  double wall_start_ = 0.0;
  std::size_t collisions_ = 0;
};

}  // namespace pslam::agent
