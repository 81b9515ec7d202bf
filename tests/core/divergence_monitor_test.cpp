// The lost-filter warning: each sign on its own from made-up filter steps, then a real filter that is
// forced to diverge (its scans suddenly come from another world), and real runs that must not warn.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "pslam/filter/divergence_monitor.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/io/carmen_reader.hpp"
#include "testing/shared_data.hpp"
#include "testing/synthetic_world.hpp"

namespace pslam {
namespace {

constexpr double kScanPeriod = 0.1;
constexpr double kGoodScore = 0.8;  // a scan that matches the map well

// Feeds made-up steps: the robot drives 5 cm per scan along x, the estimate agrees with odometry,
// every fifth scan is a filter update.
class Feeder {
 public:
  explicit Feeder(int particles = 30, const DivergenceOptions& options = {}) : monitor(particles, options) {}

  // Returns whether the state changed.
  bool Scan(double score = kGoodScore, double neff = 20.0, const Pose2D& estimate_offset = {}, double dt = kScanPeriod) {
    time_ += dt;
    odometry_ = Pose2D(odometry_.x + 0.05, odometry_.y, odometry_.theta);
    RbpfStep step;
    step.updated = (index_++ % 5) == 0;
    step.neff = neff;
    step.tracking_score = score;
    offset_ = offset_ * estimate_offset;
    step.pose = odometry_ * offset_;
    LaserScan scan;
    scan.timestamp = time_;
    scan.odometry = odometry_;
    const bool changed = monitor.Add(step, scan);
    if (changed) ++changes;
    return changed;
  }
  void Scans(int n, double score = kGoodScore, double neff = 20.0) {
    for (int i = 0; i < n; ++i) Scan(score, neff);
  }
  double time() const { return time_; }

  DivergenceMonitor monitor;
  int changes = 0;

 private:
  double time_ = 1000.0;
  int index_ = 0;
  Pose2D odometry_;
  Pose2D offset_;  // of the estimate from odometry, in the robot's frame
};

TEST(DivergenceMonitor, SteadyMatchingScansStayOk) {
  Feeder f;
  f.Scans(500);
  EXPECT_EQ(f.monitor.state(), TrackingState::kOk);
  EXPECT_EQ(f.changes, 0);
  EXPECT_TRUE(f.monitor.reason().empty());
}

TEST(DivergenceMonitor, CollapsedTrackingScoreIsLost) {
  Feeder f;
  f.Scans(50);
  f.Scans(2, 0.01);
  EXPECT_EQ(f.monitor.state(), TrackingState::kOk) << "the window still holds a good scan";
  EXPECT_TRUE(f.Scan(0.01));
  EXPECT_EQ(f.monitor.state(), TrackingState::kLost);
  EXPECT_EQ(f.monitor.changed_at_scan(), 52);
  EXPECT_NE(f.monitor.reason().find("tracking score 0.010 over the last 3 scans"), std::string::npos) << f.monitor.reason();
}

TEST(DivergenceMonitor, WeakTrackingScoreIsDegraded) {
  Feeder f;
  f.Scans(20, 0.06);
  EXPECT_EQ(f.monitor.state(), TrackingState::kDegraded);
  EXPECT_EQ(f.changes, 1);
  EXPECT_NE(f.monitor.reason().find("tracking score 0.060 over the last 10 scans"), std::string::npos) << f.monitor.reason();
}

TEST(DivergenceMonitor, PinnedNeffIsDegraded) {
  Feeder f;
  f.Scans(50);
  f.Scans(20, kGoodScore, 1.0);  // 4 updates
  EXPECT_EQ(f.monitor.state(), TrackingState::kOk);
  f.Scans(5, kGoodScore, 1.0);   // the 5th
  EXPECT_EQ(f.monitor.state(), TrackingState::kDegraded);
  EXPECT_NE(f.monitor.reason().find("N_eff 1.00"), std::string::npos) << f.monitor.reason();
}

TEST(DivergenceMonitor, NeffOfTwoParticlesSaysNothing) {
  Feeder f(2);
  f.Scans(100, kGoodScore, 1.0);
  EXPECT_EQ(f.monitor.state(), TrackingState::kOk);
}

TEST(DivergenceMonitor, PoseJumpIsDegradedUntilItIsPast) {
  DivergenceOptions options;
  Feeder f(30, options);
  f.Scans(50);
  EXPECT_TRUE(f.Scan(kGoodScore, 20.0, Pose2D(2.0, 0.0, 0.0)));
  EXPECT_EQ(f.monitor.state(), TrackingState::kDegraded);
  EXPECT_NE(f.monitor.reason().find("estimate jumped 2.00 m"), std::string::npos) << f.monitor.reason();
  const double jumped_at = f.time();
  while (f.monitor.state() != TrackingState::kOk && f.time() < jumped_at + 60.0) f.Scan();
  EXPECT_EQ(f.monitor.state(), TrackingState::kOk);
  EXPECT_NEAR(f.time() - jumped_at, options.jump_hold_seconds + options.recover_seconds, 2 * kScanPeriod);
  EXPECT_EQ(f.changes, 2);
}

TEST(DivergenceMonitor, TurnBeyondOdometryIsAJump) {
  Feeder f;
  f.Scans(50);
  f.Scan(kGoodScore, 20.0, Pose2D(0.0, 0.0, 1.0));
  EXPECT_EQ(f.monitor.state(), TrackingState::kDegraded);
}

TEST(DivergenceMonitor, ALongGapAllowsALargerCorrection) {
  Feeder f;
  f.Scans(50);
  f.Scan(kGoodScore, 20.0, Pose2D(1.4, 0.0, 0.0), 2.0);  // allowed: 1 m + 0.5 m/s * 2 s
  EXPECT_EQ(f.monitor.state(), TrackingState::kOk);
  f.Scan(kGoodScore, 20.0, Pose2D(1.4, 0.0, 0.0));
  EXPECT_EQ(f.monitor.state(), TrackingState::kDegraded);
}

TEST(DivergenceMonitor, TwoSignsAtOnceAreLost) {
  Feeder f;
  f.Scans(50);
  f.Scans(25, kGoodScore, 1.0);
  ASSERT_EQ(f.monitor.state(), TrackingState::kDegraded);
  f.Scan(kGoodScore, 1.0, Pose2D(2.0, 0.0, 0.0));
  EXPECT_EQ(f.monitor.state(), TrackingState::kLost);
  EXPECT_NE(f.monitor.reason().find("N_eff"), std::string::npos);
  EXPECT_NE(f.monitor.reason().find("jumped"), std::string::npos);
}

TEST(DivergenceMonitor, AScoreHoveringAtTheThresholdWarnsOnce) {
  Feeder f;
  f.Scans(50);
  for (int i = 0; i < 200; ++i) f.Scans(10, i % 2 ? 0.06 : 0.08);
  EXPECT_EQ(f.changes, 1);
  EXPECT_EQ(f.monitor.state(), TrackingState::kDegraded);
}

TEST(DivergenceMonitor, RecoversOnlyAfterTheBetterEvidenceHeld) {
  DivergenceOptions options;
  Feeder f(30, options);
  f.Scans(50);
  f.Scans(3, 0.01);
  ASSERT_EQ(f.monitor.state(), TrackingState::kLost);
  const double lost_at = f.time();
  while (f.monitor.state() == TrackingState::kLost && f.time() < lost_at + 60.0) f.Scan();
  EXPECT_EQ(f.monitor.state(), TrackingState::kOk) << "from lost straight to ok: the evidence is all good by then";
  // One good scan lifts the window's mean above the thresholds; from then on the evidence must hold
  // for recover_seconds.
  EXPECT_NEAR(f.time() - lost_at, kScanPeriod + options.recover_seconds, 2 * kScanPeriod);
  EXPECT_EQ(f.changes, 2);
}

// A robot driving an arc in the synthetic room; from scan 'switch_at' on its laser sees another
// room, as if it had been carried off (odometry carries on as before).
struct DriveResult {
  std::vector<TrackingState> states;  // per scan
  int changes = 0;
  std::string reason_when_lost;
};

DriveResult Drive(int scans, int switch_at) {
  RbpfOptions options;
  options.threads = 1;
  Rbpf filter(options);
  DivergenceMonitor monitor(options.particles);
  const auto room = testing::RoomWalls();
  const auto other = testing::OtherRoomWalls();
  DriveResult result;
  for (int k = 0; k < scans; ++k) {
    const double t = k * kScanPeriod;
    const double a = 0.15 * t;
    const Pose2D pose(-1.0 + 2.0 * std::sin(a), -1.5 + 1.5 * (1.0 - std::cos(a)), a);
    LaserScan scan = testing::RenderScan(pose, k >= switch_at ? other : room, pose);
    scan.timestamp = t;
    if (monitor.Add(filter.AddScan(scan), scan)) {
      ++result.changes;
      if (monitor.state() == TrackingState::kLost && result.reason_when_lost.empty()) result.reason_when_lost = monitor.reason();
    }
    result.states.push_back(monitor.state());
  }
  return result;
}

TEST(DivergenceMonitorOnTheFilter, NormalDriveStaysOk) {
  const DriveResult r = Drive(400, 400);
  EXPECT_EQ(r.changes, 0);
}

TEST(DivergenceMonitorOnTheFilter, ScansOfAnotherWorldFireTheLostWarning) {
  const DriveResult r = Drive(300, 200);
  for (int k = 0; k < 200; ++k) ASSERT_EQ(r.states[static_cast<std::size_t>(k)], TrackingState::kOk) << "scan " << k;
  int lost_at = -1;
  for (int k = 200; k < 300 && lost_at < 0; ++k) {
    if (r.states[static_cast<std::size_t>(k)] == TrackingState::kLost) lost_at = k;
  }
  ASSERT_GE(lost_at, 200) << "the filter was never reported lost";
  EXPECT_LE(lost_at, 205) << "within a few scans of the switch";
  EXPECT_NE(r.reason_when_lost.find("tracking score"), std::string::npos) << r.reason_when_lost;
}

// The first 2000 scans of the Intel log (400 s, with its first loops) with the default filter: no
// warning at all.
TEST(DivergenceMonitorOnTheFilter, IntelSliceDoesNotWarn) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  CarmenReader reader(log.string());
  ScanStream scans(reader);
  RbpfOptions options;
  Rbpf filter(options);
  DivergenceMonitor monitor(options.particles);
  int read = 0;
  while (auto scan = scans.Next()) {
    if (++read > 2000) break;
    EXPECT_FALSE(monitor.Add(filter.AddScan(*scan), *scan))
        << "scan " << monitor.changed_at_scan() << ": " << TrackingStateName(monitor.state()) << ", " << monitor.reason();
  }
}

}  // namespace
}  // namespace pslam
