#include "pslam/sim/simulator.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "pslam/common/random.hpp"

namespace pslam {
namespace {

// Events whose due time is within this of the step's end are taken now: repeated Step(0.1) calls
// add up to 0.9999999 rather than 1.0, and a scan should not slip to the next step for that.
constexpr double kTimeEpsilon = 1e-9;

std::string TimestampText(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

}  // namespace

Simulator::Simulator(World world, const Pose2D& start, const SimulatorOptions& options)
    : world_(std::move(world)),
      options_(options),
      odometry_(start, options.odometry_noise, options.seed),
      laser_rng_(MakeStream(options.seed, 0x1A5, 0)),
      time_(options.start_time_seconds),
      true_pose_(start) {
  if (!(options_.scan_rate_hz > 0.0) || !(options_.odometry_rate_hz > 0.0) || !(options_.physics_step_seconds > 0.0)) {
    throw std::invalid_argument("simulator rates and physics step must be positive");
  }
  if (!world_.IsDiscFree(start.translation(), options_.drive.robot_radius)) {
    throw std::invalid_argument("simulator start pose is not in free space");
  }
}

void Simulator::Teleport(const Pose2D& pose) {
  if (!world_.IsDiscFree(pose.translation(), options_.drive.robot_radius)) {
    throw std::invalid_argument("teleport target is not in free space");
  }
  true_pose_ = pose;
  velocity_ = command_ = Twist{};
}

void Simulator::SetCommand(const Twist& command) { command_ = ClampToSpeedLimits(command, options_.drive); }

StepResult Simulator::Step(double dt) {
  StepResult result;
  const double end = time_ + std::max(dt, 0.0);
  while (true) {
    // Due times from the index, not by accumulation, so they never drift.
    const double scan_due = options_.start_time_seconds + static_cast<double>(next_scan_index_) / options_.scan_rate_hz;
    const double odometry_due =
        options_.start_time_seconds + static_cast<double>(next_odometry_index_) / options_.odometry_rate_hz;
    const double due = std::min(scan_due, odometry_due);
    if (due > end + kTimeEpsilon) break;
    if (AdvanceTo(std::max(due, time_))) result.collided = true;
    if (odometry_due <= due) {
      result.events.push_back({time_, true_pose_, MakeOdometryReading()});
      ++next_odometry_index_;
    }
    if (scan_due <= due) {
      result.events.push_back({time_, true_pose_, MakeScan()});
      ++next_scan_index_;
    }
  }
  if (AdvanceTo(std::max(end, time_))) result.collided = true;
  return result;
}

bool Simulator::AdvanceTo(double until) {
  bool collided = false;
  while (until - time_ > kTimeEpsilon) {
    const double dt = std::min(options_.physics_step_seconds, until - time_);
    if (Tick(dt)) collided = true;
    time_ += dt;
  }
  time_ = until;
  return collided;
}

bool Simulator::Tick(double dt) {
  const Twist velocity = StepVelocity(velocity_, command_, dt, options_.drive);
  const Pose2D next = IntegrateArc(true_pose_, velocity, dt);
  if (!world_.IsDiscFree(next.translation(), options_.drive.robot_radius)) {
    velocity_ = {};
    command_ = {};
    ++collision_count_;
    return true;
  }
  odometry_.Advance(Between(true_pose_, next));
  true_pose_ = next;
  velocity_ = velocity;
  return false;
}

OdometryReading Simulator::MakeOdometryReading() const {
  OdometryReading reading;
  reading.timestamp = time_;
  reading.pose = odometry_.pose();
  reading.translational_velocity = velocity_.linear;
  reading.rotational_velocity = velocity_.angular;
  return reading;
}

LaserScan Simulator::MakeScan() {
  LaserScan scan = SimulateScan(world_, true_pose_, options_.laser, laser_rng_);
  scan.timestamp = time_;
  scan.timestamp_text = TimestampText(time_);
  scan.odometry = odometry_.pose();
  return scan;
}

}  // namespace pslam
