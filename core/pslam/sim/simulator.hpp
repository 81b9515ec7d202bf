#pragma once
// A Pioneer 3-DX with a SICK LMS-200 in a World, on a simulated clock: the stand-in for Player/Stage
// in the paper's simulations (Sec. V-A). Step(dt) advances physics in small ticks and returns the
// odometry readings and scans that fell due, in time order; nothing waits on a wall clock, so an
// exploration of hundreds of simulated seconds runs in a fraction of a second. Deterministic for a
// seed: odometry drift and range noise come from separate seeded streams.
#include <cstddef>
#include <cstdint>
#include <random>
#include <variant>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/sensor/laser_scan.hpp"
#include "pslam/sim/diff_drive.hpp"
#include "pslam/sim/laser_model.hpp"
#include "pslam/sim/odometry_model.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

struct SimulatorOptions {
  DiffDriveOptions drive;
  OdometryNoiseOptions odometry_noise;
  LaserOptions laser;
  double scan_rate_hz = 5.0;             // like the Intel Research Lab log
  double odometry_rate_hz = 10.0;
  double physics_step_seconds = 0.01;    // 2 mm per tick at top speed: no tunnelling through walls
  double start_time_seconds = 0.0;       // clock value of the first events
  std::uint64_t seed = 1;
};

// One emitted event: an odometry reading or a scan (whose odometry field is the odometry pose at
// the same instant), with the ground truth at that instant for evaluation.
struct SimulatorEvent {
  double time = 0.0;
  Pose2D true_pose;
  std::variant<OdometryReading, LaserScan> data;
};

struct StepResult {
  std::vector<SimulatorEvent> events;  // in time order; odometry before a scan of the same instant
  bool collided = false;               // a commanded motion was stopped by an obstacle
};

class Simulator {
 public:
  // Throws std::invalid_argument when the robot's disc at 'start' is not entirely in free space,
  // or when a rate or the physics step is not positive.
  Simulator(World world, const Pose2D& start, const SimulatorOptions& options = {});

  // The velocity command (clamped to the speed limits) the robot tracks from now on, within the
  // acceleration limits, until the next call or until a collision cancels it.
  void SetCommand(const Twist& command);

  // Advances the clock by 'dt' seconds. Events are due at start_time + k / rate (k = 0, 1, ...), so
  // the first Step also reports the start state. A tick whose motion would make the robot's disc
  // touch a non-free cell is not taken: the robot stops where it is, the command is cancelled
  // (zeroed), and the result says collided.
  StepResult Step(double dt);

  // Carries the robot to 'pose' at standstill, as when someone picks it up: odometry does not see
  // it move (the kidnapped robot problem). Throws std::invalid_argument when the robot's disc at
  // 'pose' is not entirely in free space.
  void Teleport(const Pose2D& pose);

  double time() const { return time_; }
  const Pose2D& true_pose() const { return true_pose_; }  // ground truth, for tests and experiments
  const Pose2D& odometry_pose() const { return odometry_.pose(); }
  const Twist& velocity() const { return velocity_; }
  const Twist& command() const { return command_; }
  std::size_t collision_count() const { return collision_count_; }
  const World& world() const { return world_; }
  const SimulatorOptions& options() const { return options_; }

 private:
  // Runs physics ticks until the clock reads 'until'; returns whether any tick collided.
  bool AdvanceTo(double until);
  bool Tick(double dt);
  OdometryReading MakeOdometryReading() const;
  LaserScan MakeScan();

  World world_;
  SimulatorOptions options_;
  DriftingOdometry odometry_;
  std::mt19937_64 laser_rng_;
  double time_;
  std::uint64_t next_scan_index_ = 0;
  std::uint64_t next_odometry_index_ = 0;
  Pose2D true_pose_;
  Twist velocity_;
  Twist command_;
  std::size_t collision_count_ = 0;
};

}  // namespace pslam
