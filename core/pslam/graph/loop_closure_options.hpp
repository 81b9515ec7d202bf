#pragma once
// Every tunable of loop closure, with its default, in one place.
#include "pslam/matching/scan_matcher.hpp"

namespace pslam {

struct LoopClosureOptions {
  // Off unless turned on: `pslam run` maps logs with it. In simulated explorations it improved
  // full-coverage runs but made P-SLAM's skip runs worse (docs/loop-closure.md), so explorations,
  // the experiments and server sessions go without.
  bool enabled = false;
  // Submaps: consecutive filter updates (nodes) rendered into one rigid local grid.
  int nodes_per_submap = 25;
  int recent_submaps = 2;          // the newest submaps are what tracking matches against: skipped
  // Which nodes look for a closure, and where.
  int check_every_nodes = 3;
  int max_candidates = 3;          // nearest eligible submaps tried per check
  // Judge a place across every submap searched, not within each: a copy of the robot's
  // surroundings in another submap is then a rival too, and submaps closed a moment ago are
  // searched as possible rivals. Off by default: on Intel it refused closures the map needed
  // (docs/loop-closure.md); give it max_candidates 8 or so to see the copies next door.
  bool judge_across_submaps = false;
  int context_nodes = 5;           // the newest nodes' hits together form the matched cloud
  double cloud_spacing = 0.15;     // metres between kept cloud points
  double cloud_max_range = 12.0;   // metres from the node
  // The search windows grow with the graph distance from the node to the submap: the shortest path
  // through the pose graph, where the filter's motion counts its length and a closure counts
  // closure_length. Right after a loop was closed the robot's place in the old map is known to
  // centimetres; after a long excursion it may be metres and tens of degrees off. Measured on the
  // three benchmark logs at seeds 1-5 (docs/loop-closure.md): wider windows (0.2 m/m up to 7 m) let
  // a wrong closure bend Intel at seed 5, narrower ones (0.05 m/m up to 3 m) miss the closure that
  // FR079 needs at seed 2.
  double base_window = 1.0;        // metres
  double window_per_metre = 0.1;
  double max_window = 5.0;         // metres
  double base_angular_window = 0.15;    // radians each way
  double angular_window_per_metre = 0.02;
  double max_angular_window = 0.5;
  double closure_length = 0.5;      // metres
  int rest_after_closure = 8;      // nodes without a search after a closure: it holds for a while
  int search_depth = 6;            // max-pooled levels of the branch-and-bound search (2^6 cells)
  double min_score = 0.55;         // mean occupancy probability of the matched cloud
  // A closure is ambiguous (a repeated room, a uniform corridor) when a pose this far from the
  // best one scores nearly as well: it is not used.
  double ambiguity_distance = 0.6;     // metres
  double ambiguity_angle = 0.25;       // radians
  double ambiguity_ratio = 0.92;       // alternative score / best score
  // Rivals are looked for at least this far (metres each way) around the guess, however narrow the
  // window the closure itself must lie in: inside a window narrower than ambiguity_distance a
  // match sliding along a corridor has no room for a rival and would pass as unique.
  double min_rival_window = 1.5;
  ScanMatchOptions refine{.coarsest_level = 0, .max_correction_translation = 0.15, .max_correction_rotation = 0.1};
  // Pose graph: standard deviations of the filter's relative motion between two updates and of a
  // closure; closures carry a Huber loss and are dropped when they disagree with the optimum.
  double odometry_sigma_xy = 0.02;     // metres
  double odometry_sigma_theta = 0.01;  // radians
  double loop_sigma_xy = 0.05;
  double loop_sigma_theta = 0.02;
  double huber_scale = 2.0;            // in standard deviations
  double outlier_sigma = 6.0;          // a closure further off than this after optimising is removed
  // When to optimise: after new closures, once every so many nodes, or at once when a closure
  // moves the robot further than immediate_correction.
  int optimize_every_nodes = 40;
  double immediate_correction = 0.1;   // metres
  // The filter's maps are re-rendered from the optimised poses when some node moved this far.
  double rebuild_translation = 0.05;   // metres
  double rebuild_rotation = 0.01;      // radians
  int cached_search_grids = 16;        // max-pooled submap stacks kept between checks
};

}  // namespace pslam
