#include "pslam/filter/divergence_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>
#include <vector>

namespace pslam {
namespace {

template <typename... Args>
std::string Format(const char* format, Args... args) {
  char text[160];
  std::snprintf(text, sizeof text, format, args...);
  return text;
}

}  // namespace

const char* TrackingStateName(TrackingState state) {
  switch (state) {
    case TrackingState::kOk: return "ok";
    case TrackingState::kDegraded: return "degraded";
    case TrackingState::kLost: return "lost";
  }
  return "ok";
}

DivergenceMonitor::DivergenceMonitor(int particles, const DivergenceOptions& options)
    : options_(options), check_neff_(particles > 2.0 * options.neff_pinned) {
  options_.collapse_window = std::max(1, options_.collapse_window);
  options_.weak_window = std::max(1, options_.weak_window);
}

std::optional<double> DivergenceMonitor::MeanScore(int window) const {
  if (static_cast<int>(scores_.size()) < window) return std::nullopt;
  return std::accumulate(scores_.end() - window, scores_.end(), 0.0) / static_cast<double>(window);
}

bool DivergenceMonitor::Add(const RbpfStep& step, const LaserScan& scan) {
  const double time = scan.timestamp;
  const int index = scans_++;
  if (index > 0) {  // the first scan only starts the map: nothing to match or to move from
    scores_.push_back(step.tracking_score);
    if (static_cast<int>(scores_.size()) > std::max(options_.collapse_window, options_.weak_window)) scores_.pop_front();

    if (step.updated) {
      const bool pinned = check_neff_ && step.neff < options_.neff_pinned;
      pinned_updates_ = pinned ? pinned_updates_ + 1 : 0;
      if (pinned) pinned_neff_ = step.neff;
    }

    // Odometry is credited with all of its motion, however fast: real logs carry odometry that
    // turns by 0.9 rad between scans 15 ms apart.
    const double dt = std::max(0.0, time - last_time_);
    // A loop closure moves the map frame, not the robot: compare in the corrected frame.
    if (step.loop_corrected) last_pose_ = step.correction * last_pose_;
    const double extra_translation = (step.pose.translation() - last_pose_.translation()).norm() -
                                     (scan.odometry.translation() - last_odometry_.translation()).norm();
    const double extra_rotation = std::abs(NormalizeAngle(step.pose.theta - last_pose_.theta)) -
                                  std::abs(NormalizeAngle(scan.odometry.theta - last_odometry_.theta));
    if (extra_translation > options_.jump_translation + options_.jump_slip_speed * dt ||
        extra_rotation > options_.jump_rotation + options_.jump_slip_turn_rate * dt) {
      jumped_ = true;
      last_jump_time_ = time;
      last_jump_translation_ = extra_translation;
      last_jump_rotation_ = extra_rotation;
    }
  }
  last_pose_ = step.pose;
  last_odometry_ = scan.odometry;
  last_time_ = time;

  const Signs signs = Assess(time);
  if (signs.level >= state_) {
    improving_ = false;
    reason_ = signs.reason;
    if (signs.level == state_) return false;
  } else {
    if (!improving_) {
      improving_ = true;
      improving_since_ = time;
    }
    if (time - improving_since_ < options_.recover_seconds) return false;
    improving_ = false;
    reason_ = signs.reason;
  }
  state_ = signs.level;
  changed_at_scan_ = index;
  changed_at_time_ = time;
  return true;
}

DivergenceMonitor::Signs DivergenceMonitor::Assess(double time) const {
  std::vector<std::string> seen;
  const std::optional<double> recent = MeanScore(options_.collapse_window);
  const std::optional<double> longer = MeanScore(options_.weak_window);
  const bool collapsed = recent && *recent < options_.score_lost;
  if (collapsed) {
    seen.push_back(Format("tracking score %.3f over the last %d scans", *recent, options_.collapse_window));
  } else if (longer && *longer < options_.score_degraded) {
    seen.push_back(Format("tracking score %.3f over the last %d scans", *longer, options_.weak_window));
  }
  if (pinned_updates_ >= options_.neff_pinned_updates) {
    seen.push_back(Format("N_eff %.2f, below %.2f for %d updates", pinned_neff_, options_.neff_pinned, pinned_updates_));
  }
  if (jumped_ && time - last_jump_time_ <= options_.jump_hold_seconds) {
    seen.push_back(Format("estimate jumped %.2f m, %.2f rad beyond odometry %.1f s ago", std::max(0.0, last_jump_translation_),
                          std::max(0.0, last_jump_rotation_), time - last_jump_time_));
  }
  Signs signs;
  if (collapsed || seen.size() >= 2) signs.level = TrackingState::kLost;
  else if (!seen.empty()) signs.level = TrackingState::kDegraded;
  for (const std::string& s : seen) signs.reason += (signs.reason.empty() ? "" : "; ") + s;
  return signs;
}

}  // namespace pslam
