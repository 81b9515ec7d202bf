#include "sources/sim_source.hpp"

#include <chrono>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "common/clock.hpp"
#include "common/log.hpp"
#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam::agent {
namespace {

constexpr const char* kDefaultWorld = "maze";
constexpr double kFastStepSeconds = 0.02;  // simulated time per step when running flat out

ShippedWorld LoadSimWorld(const std::string& spec) {
  const std::string name = spec.empty() ? kDefaultWorld : spec;
  if (name == "maze") return MakeMazeWorld();
  if (name == "office") return MakeOfficeWorld();
  if (name == "irregular") return MakeIrregularWorld();
  ShippedWorld w{name, "world file " + name, LoadWorld(name), Pose2D()};
  const auto start = ReadStartPose(name);
  if (!start) throw std::runtime_error("world " + name + " has no '# start: x, y, theta' line");
  w.start = *start;
  return w;
}

}  // namespace

SimSource::SimSource(SimSourceOptions options) : options_(std::move(options)) {
  ShippedWorld world = LoadSimWorld(options_.world);
  SimulatorOptions sim;
  sim.scan_rate_hz = options_.scan_rate_hz;
  sim.odometry_rate_hz = options_.odometry_rate_hz;
  sim.seed = options_.seed;
  // Stamp simulated events on the agent's clock, so they look like a live robot's.
  sim.start_time_seconds = AgentClock::Now();
  simulator_ = std::make_unique<Simulator>(std::move(world.world), world.start, sim);
  sim_start_ = simulator_->time();
  wall_start_ = AgentClock::Now();
  std::ostringstream d;
  d << "simulator in world '" << world.name << "' at ";
  if (options_.rate > 0) {
    d << options_.rate << "x real time";
  } else {
    d << "maximum rate";
  }
  description_ = d.str();
}

LaserDescription SimSource::laser() const {
  const LaserOptions& l = simulator_->options().laser;
  return {l.angle_min, l.angle_increment, static_cast<std::size_t>(l.beam_count), l.max_range, 0.0, l.sensor_offset};
}

std::optional<SourceEvent> SimSource::Next(double timeout_s) {
  const double deadline = AgentClock::Now() + timeout_s;
  while (true) {
    if (!pending_.empty()) {
      SourceEvent e = std::move(pending_.front());
      pending_.pop_front();
      return e;
    }
    const double target = options_.rate > 0 ? sim_start_ + (AgentClock::Now() - wall_start_) * options_.rate
                                             : simulator_->time() + kFastStepSeconds;
    if (target > simulator_->time()) {
      StepResult r = simulator_->Step(target - simulator_->time());
      if (r.collided) {
        ++collisions_;
        PSLAM_LOG(kWarning) << "simulated robot collided at (" << simulator_->true_pose().x << ", "
                            << simulator_->true_pose().y << ")";
      }
      for (auto& e : r.events) pending_.push_back(std::move(e.data));  // ground truth stays in the sim
      if (!pending_.empty()) continue;
    }
    const double left = deadline - AgentClock::Now();
    if (left <= 0) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::duration<double>(std::min(left, 0.005)));
  }
}

void SimSource::Drive(const VelocityCommand& command) { simulator_->SetCommand(Twist{command.v, command.w}); }

std::string SimSource::StatsLine() const {
  std::ostringstream out;
  out << "sim t=" << simulator_->time() - sim_start_ << " s, " << collisions_ << " collision(s)";
  return out.str();
}

}  // namespace pslam::agent
