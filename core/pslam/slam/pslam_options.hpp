#pragma once
// Every tunable of P-SLAM as a whole: the filter, the predictor, and how hypotheses are judged.
#include "pslam/filter/rbpf_options.hpp"
#include "pslam/predict/predictor_options.hpp"

namespace pslam {

struct HypothesisJudgeOptions {
  // Once this share of a hypothesis's cells has been observed, it is judged: confirmed when Psi
  // against what was observed (eq. 5) reaches confirm_psi, refuted otherwise. The paper counts
  // Psi >= 0.4 as "a reasonable-quality similar structure" (section III-C).
  double judge_observed_fraction = 0.5;
  double confirm_psi = 0.4;
  // A hypothesis none of whose cells has been observed for this long (log or simulated time)
  // expires: the robot went elsewhere, and the prediction no longer steers anything.
  double expiry_s = 300.0;
};

// For recorded logs, which have no planner: the target is the frontier the robot is heading
// toward (see heading_target.hpp).
struct HeadingTargetOptions {
  double max_distance = 8.0;        // metres ahead of the robot
  double max_bearing = 1.0;         // radians either side of the heading
  double retarget_distance = 3.0;   // pick a new target after driving this far
};

struct PSlamOptions {
  RbpfOptions filter;
  PredictorOptions predictor;
  bool predict = true;              // false: the plain RBPF, for comparison
  bool heading_targets = false;     // choose targets from the heading (logs); else SetTarget()
  HypothesisJudgeOptions judge;
  HeadingTargetOptions heading;
};

}  // namespace pslam
