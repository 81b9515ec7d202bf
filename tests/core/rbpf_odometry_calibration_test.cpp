// Online odometry calibration: how much wheel odometry overstates every metre is learned where the
// scan pins the pose down, so that it can be corrected where the scan cannot.
#include <gtest/gtest.h>

#include <variant>

#include "pslam/filter/odometry_calibration.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/sim/simulator.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {
namespace {

constexpr double kResolution = 0.05;
constexpr double kOdometryScale = 1.03;  // the wheels report 3 % more than the robot drives

// A 2 m wide corridor, 30 m long (x from 0 to 30 m), with pillars every metre on alternating walls:
// the scan fixes the position along it everywhere.
World Corridor() {
  const int length = 600, width = 40;
  World world(kResolution, CellBox{{-1, -1}, {length + 1, width + 1}}, WorldCell::kFree);
  for (int x = -1; x <= length + 1; ++x) {
    for (int y = -1; y <= width + 1; ++y) {
      const bool wall = x <= 0 || y <= 0 || x >= length || y >= width;
      const int metre = x / 20;
      const bool pillar = x % 20 < 4 && (metre % 2 == 0 ? y < 6 : y > width - 6);
      if (wall || pillar) world.Set({x, y}, WorldCell::kOccupied);
    }
  }
  return world;
}

// Drives 12 m straight along the corridor with the overstating odometry; returns the scale the
// filter learned for it.
double LearnedScale(bool calibrate) {
  const Pose2D start(1.0, 1.0, 0.0);
  SimulatorOptions sim_options;
  sim_options.odometry_noise = OdometryNoiseOptions{0.0, 0.0, 0.0, 0.0, 0.0};
  Simulator sim(Corridor(), start, sim_options);
  RbpfOptions options;
  options.particles = 8;
  options.threads = 1;
  options.initial_pose = start;
  options.points.max_usable_range = 8.0;
  options.points.no_return_free_range = 7.9;  // the degeneracy guard is on by default
  options.odometry_calibration.enabled = calibrate;
  Rbpf filter(options);
  Pose2D odometry = start, previous_truth = start;
  sim.SetCommand({0.5, 0.0});
  while (sim.true_pose().x < 13.0) {
    for (const SimulatorEvent& e : sim.Step(0.2).events) {
      const auto* scan = std::get_if<LaserScan>(&e.data);
      if (!scan) continue;
      const Pose2D step = Between(previous_truth, e.true_pose);
      odometry = odometry * Pose2D(step.x * kOdometryScale, step.y * kOdometryScale, step.theta);
      previous_truth = e.true_pose;
      LaserScan biased = *scan;
      biased.odometry = odometry;
      filter.AddScan(biased);
    }
  }
  return filter.odometry_calibration().translation_scale();
}

TEST(RbpfOdometryCalibrationTest, TheFilterLearnsHowMuchItsOdometryOverstates) {
  EXPECT_NEAR(LearnedScale(true), 1.0 / kOdometryScale, 0.005);
  EXPECT_EQ(LearnedScale(false), 1.0) << "off: odometry is taken as it is";
}

TEST(OdometryCalibrationTest, LearnsOnlyFromPairsOfConstrainedScans) {
  OdometryCalibrationOptions options;
  options.enabled = true;
  OdometryCalibration calibration(options);
  Pose2D truth, odometry;
  auto drive = [&](int scans, bool constrained) {
    for (int i = 0; i < scans; ++i) {
      const Pose2D step(0.05, 0.0, 0.03);
      truth = truth * step;
      odometry = odometry * Pose2D(step.x * 1.05, 0.0, step.theta * 0.97);
      // Where the scan does not constrain the pose, the match just follows odometry.
      calibration.AddScan(odometry, constrained ? truth : odometry, constrained);
    }
  };
  drive(40, false);
  EXPECT_EQ(calibration.translation_scale(), 1.0) << "nothing learned from unconstrained matches";
  drive(40, true);  // 39 pairs, 2 m and 1.1 rad: below the evidence needed
  EXPECT_EQ(calibration.translation_scale(), 1.0);
  drive(100, true);
  EXPECT_NEAR(calibration.translation_scale(), 1.0 / 1.05, 1e-3);
  EXPECT_NEAR(calibration.rotation_scale(), 1.0 / 0.97, 1e-3);
  const Pose2D corrected = calibration.Correct(Pose2D(1.05, 0.0, 0.97));
  EXPECT_NEAR(corrected.x, 1.0, 1e-3);
  EXPECT_NEAR(corrected.theta, 1.0, 1e-3);
  // A slip: the match moves 0.55 m in one scan while odometry moves 5 cm. It is not taken for a scale.
  truth = truth * Pose2D(0.55, 0.0, 0.0);
  odometry = odometry * Pose2D(0.0525, 0.0, 0.0);
  calibration.AddScan(odometry, truth, true);
  EXPECT_NEAR(calibration.translation_scale(), 1.0 / 1.05, 1e-3);
}

TEST(OdometryCalibrationTest, StaysWithinItsBoundsAndIsOffWhenDisabled) {
  OdometryCalibrationOptions options;
  options.enabled = true;
  options.max_scale_error = 0.02;
  OdometryCalibration bounded(options);
  options.enabled = false;
  OdometryCalibration disabled(options);
  Pose2D truth, odometry;
  for (int i = 0; i < 200; ++i) {
    truth = truth * Pose2D(0.05, 0.0, 0.0);
    odometry = odometry * Pose2D(0.05 * 1.05, 0.0, 0.0);
    bounded.AddScan(odometry, truth, true);
    disabled.AddScan(odometry, truth, true);
  }
  EXPECT_NEAR(bounded.translation_scale(), 0.98, 1e-9);
  EXPECT_EQ(disabled.translation_scale(), 1.0);
}

}  // namespace
}  // namespace pslam
