#pragma once
// Thresholds of the divergence monitor (divergence_monitor.hpp), with their defaults, measured on
// the Intel, ACES and FR079 logs (30 particles, no predictions): at seed 1 no threshold is crossed
// on any of them. README.md ("When the filter is lost") has the figures, and those of other seeds.
#include <string>
#include <vector>

namespace pslam {

struct DivergenceOptions {
  // Tracking score: mean map evidence at the scan endpoints after tracking (RbpfStep), averaged over
  // the last scans. Scans of another place than the map's mostly score below 0.03, but only until
  // the next filter update puts them into the map, which can be a few scans later: a collapse is
  // seen over a short window. At seed 1 the lowest 3-scan mean on the logs is 0.072 (ACES), the lowest
  // 10-scan mean 0.084 (FR079, a stretch where scan matching falls back to odometry).
  int collapse_window = 3;            // scans
  double score_lost = 0.03;
  int weak_window = 10;               // scans
  double score_degraded = 0.07;
  // N_eff pinned at its minimum: one particle carries all the weight, update after update, so the
  // filter cannot correct itself any more. On the logs N_eff stays below 3 for one update at most.
  double neff_pinned = 1.5;
  int neff_pinned_updates = 5;        // consecutive filter updates
  // Pose jump: the estimate moves further between two scans than odometry says, by more than a
  // particle switch or a snap onto old structure explains (at most 0.51 m and 0.34 rad on the
  // logs), plus what slip could add over the time between the scans.
  double jump_translation = 1.0;      // metres
  double jump_rotation = 0.7;         // radians
  double jump_slip_speed = 0.5;       // metres per second between the scans
  double jump_slip_turn_rate = 0.5;   // radians per second between the scans
  double jump_hold_seconds = 5.0;     // a jump is reported for this long
  // The state improves only after the better evidence has held this long, so that a score hovering
  // around a threshold gives one warning, not one per scan.
  double recover_seconds = 3.0;
};

// Sets one option by its name (e.g. "score_lost") from text. Returns an empty string on success,
// or what is wrong; unknown names are rejected.
std::string SetDivergenceOption(DivergenceOptions& options, const std::string& name, const std::string& value);

// Names of every option SetDivergenceOption accepts, for help texts.
std::vector<std::string> DivergenceOptionNames();

}  // namespace pslam
