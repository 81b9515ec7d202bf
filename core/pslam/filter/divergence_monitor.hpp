#pragma once
// Watches the particle filter for signs that it no longer knows where the robot is, so that an
// operator can be warned while the run goes on. Three signs, each from what a filter step reports:
//  - the scans stop matching the map: the tracking score stays low;
//  - the particle set has collapsed: N_eff stays pinned at its minimum, update after update;
//  - the estimate jumps: it moves far further between two scans than odometry says.
// One sign makes the state 'degraded'; a collapsed tracking score, or two signs at once, 'lost'.
#include <deque>
#include <optional>
#include <string>

#include "pslam/filter/divergence_options.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam {

enum class TrackingState { kOk, kDegraded, kLost };

// "ok", "degraded" or "lost".
const char* TrackingStateName(TrackingState state);

class DivergenceMonitor {
 public:
  // 'particles': the filter's particle count (N_eff says nothing about collapse with one or two).
  explicit DivergenceMonitor(int particles, const DivergenceOptions& options = {});

  // Takes the filter's step for 'scan' (its time and odometry); returns true when the state changed.
  bool Add(const RbpfStep& step, const LaserScan& scan);

  TrackingState state() const { return state_; }
  // Why the state is not ok: the signs seen, e.g. "tracking score 0.009 over the last 3 scans".
  // Empty when ok.
  const std::string& reason() const { return reason_; }
  // The scan index (counting every scan taken) and time at which the state last changed.
  int changed_at_scan() const { return changed_at_scan_; }
  double changed_at_time() const { return changed_at_time_; }

 private:
  struct Signs {
    TrackingState level = TrackingState::kOk;
    std::string reason;
  };
  Signs Assess(double time) const;
  std::optional<double> MeanScore(int window) const;  // of the last 'window' scans; none while fewer

  DivergenceOptions options_;
  bool check_neff_;
  std::deque<double> scores_;        // tracking scores of the last scans
  int pinned_updates_ = 0;           // consecutive updates with N_eff pinned
  double pinned_neff_ = 0.0;         // the last of them
  double last_jump_time_ = 0.0;
  double last_jump_translation_ = 0.0, last_jump_rotation_ = 0.0;
  bool jumped_ = false;
  Pose2D last_pose_, last_odometry_;
  double last_time_ = 0.0;
  int scans_ = 0;

  TrackingState state_ = TrackingState::kOk;
  std::string reason_;
  int changed_at_scan_ = 0;
  double changed_at_time_ = 0.0;
  bool improving_ = false;           // the evidence has been better than the state since ...
  double improving_since_ = 0.0;     // ... this time
};

}  // namespace pslam
