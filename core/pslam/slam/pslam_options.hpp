#pragma once
// Every tunable of P-SLAM as a whole: the filter, the predictor, and how hypotheses are judged.
#include "pslam/filter/rbpf_options.hpp"
#include "pslam/predict/library_map.hpp"
#include "pslam/predict/predictor_options.hpp"

namespace pslam {

struct HypothesisJudgeOptions {
  // Once this share of a hypothesis's cells has been observed, and that part holds at least
  // min_structure_m of wall on the predicted or the observed side (hypothesis_judge.hpp), it is
  // judged: confirmed when Psi against what was observed (eq. 5) reaches confirm_psi, refuted
  // otherwise. The paper counts Psi >= 0.4 as "a reasonable-quality similar structure" (section
  // III-C); min_structure_m is the predictor's bar for S_f (PredictorOptions::min_structure_m).
  double judge_observed_fraction = 0.5;
  double min_structure_m = 4.0;
  double confirm_psi = 0.4;
  // A hypothesis is drawn on the best map as it was when predicted; by the time the robot maps
  // that region, the filter has moved the map there by a few centimetres, more than Psi's
  // one-cell tolerance. So before a refutation the hypothesis is judged once more at its best
  // whole-cell shift within this distance: the question is whether the predicted structure is
  // there, not whether the map stood still. On maze seed 13 (threshold 0.7) all 4 refuted
  // hypotheses matched the true world at Psi 0.81-0.97, and scored 0.75-0.93 against the map
  // 1-3 cells over. 0: no second look.
  double registration_m = 0.15;
  // A pending hypothesis none of whose cells has been observed for this long (log or simulated
  // time) expires: the robot went elsewhere, so it leaves the particle weights (nothing checks it
  // any more). It still covers its cells for exploration: nothing contradicted it, and skipping
  // such regions is the point of predicting them. Observed later and refuted, it uncovers them.
  double expiry_s = 300.0;
  // Where an observed cell contradicts a hypothesis (local_refutation.hpp; walls within
  // registration_m of each other agree), its cells within this distance that the robot has not
  // seen are withdrawn: rooms of one plan differ in where their furniture stands. 0: never.
  double local_refutation_radius_m = 1.0;
  // Predicted floor cut off from all the floor the robot has seen, and the walls that bound only
  // it, are taken out of a hypothesis when it is accepted and after each withdrawal
  // (sealed_predictions.hpp): a room copied onto space seen closed has no way in. Off: it makes
  // merged maps truer (held-out worlds 8 -> 11 of 15 at merged Psi >= 0.7) but predicts less, and
  // exploration saves less time (25.7 -> 15.6 %, maze 34.4 -> 20.0 %; docs/experiments.md).
  bool drop_sealed_off = false;
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
  // The paper predicts "only when a new target is selected" (section IV-B). A planner replanning
  // toward the same frontier moves its target cell as the frontier recedes; a target this close
  // to the one last predicted for is the same exploration goal and starts no new prediction.
  // A quarter of the region size d: the new S_f would overlap the last one by over half.
  double new_target_distance_m = 2.5;
  // Predict from MergedMap() (the best map with the hypotheses not refuted written in) instead of
  // the best map alone: predicted walls then serve as the target's surroundings, its control point
  // and references too. For an explorer that plans on the merged map (the paper's "virtual
  // mapping", Sec. II-B), whose targets lie at the edge of what is predicted: there the observed
  // map seldom has a corner near enough to be the control point, and the prediction stops where
  // the first one ended. Errors then carry from one hypothesis into the next; the maze
  // experiment's merged Psi against the true world measures how far.
  bool predict_on_merged_map = false;
  // ... but only from hypotheses that reached this Psi in the search, or that observation has
  // confirmed. One made at a lower threshold still covers its cells and weighs the particles, but
  // no prediction builds on it until the robot has seen it right: a wrong one would otherwise
  // seed a wrong but self-consistent chain. 0.7 is the paper's conservative threshold (section
  // III-C), so at the predictor's default this changes nothing. Maze at threshold 0.6, seeds
  // 1-18: 5 runs ended with merged Psi below 0.7 without it, 1 with it.
  double predict_from_psi = 0.7;
  HypothesisJudgeOptions judge;
  HeadingTargetOptions heading;
  // Other maps of the site the predictor searches for references too (library_map.hpp), made
  // with 'predictor'; shared and immutable, so copying the options is cheap.
  MapLibrary library;
};

}  // namespace pslam
