#include "source_factory.hpp"

#include "sources/log_source.hpp"
#include "sources/pioneer_source.hpp"
#include "sources/sim_source.hpp"

namespace pslam::agent {

std::unique_ptr<ScanSource> MakeSource(const AgentOptions& o) {
  switch (o.source) {
    case SourceKind::kSim: {
      SimSourceOptions sim;
      sim.world = o.source_target;
      sim.rate = o.rate;
      sim.scan_rate_hz = o.sim_scan_rate_hz;
      return std::make_unique<SimSource>(sim);
    }
    case SourceKind::kLog:
      return std::make_unique<LogSource>(LogSourceOptions{o.source_target, o.rate, o.max_scans});
    case SourceKind::kPioneer: {
      PioneerSourceOptions p;
      p.robot_device = o.source_target;
      p.laser_device = o.laser_device;
      p.robot.baud = o.robot_baud;
      p.robot.enable_motors = o.drive;
      p.laser.baud = o.laser_baud;
      p.laser_offset = o.laser_offset;
      return std::make_unique<PioneerSource>(p);
    }
  }
  return nullptr;
}

}  // namespace pslam::agent
