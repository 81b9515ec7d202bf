#pragma once
// Choosing where to explore next: the reachable frontier cluster with the lowest path cost less
// what it is worth (its length, capped, and a bonus for the goal the robot already drives to).
//
// Two modes, as in the paper's maze simulation (Sec. V-A1): full coverage visits every frontier,
// and skip-predicted leaves out frontiers whose unknown surroundings are already covered by
// accepted structure hypotheses (the caller's predicate), which is how P-SLAM saves exploration
// time. One Dijkstra search from the robot ranks the clusters in order of path cost, and stops as
// soon as no cluster farther out could beat the best one found: the cost of a plan grows with the
// distance to the next target, not with the size of the map.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <vector>

#include "pslam/explore/frontier.hpp"
#include "pslam/explore/path_planner.hpp"
#include "pslam/explore/planning_grid.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

enum class ExploreMode { kFullCoverage, kSkipPredicted };

struct ExploreOptions {
  ExploreMode mode = ExploreMode::kFullCoverage;
  FrontierOptions frontier;
  PlannerOptions planner;
  // Skip-predicted: a cluster is skipped when at least skip_covered_fraction of the unknown cells
  // within skip_radius of it (reached through unknown space, not through predicted walls) are
  // covered.
  double skip_radius = 2.0;             // m
  double skip_covered_fraction = 0.8;
  // Unknown cells within this many cells of a wall (mapped or predicted) are counted but not passed
  // through: a wall seen at a grazing angle has gaps of a cell or two, and through them the count
  // would reach the unknown interior of an obstacle, which nothing ever predicts. 2 cells (10 cm)
  // closes gaps of up to 4 cells, far narrower than any doorway.
  int wall_seal_cells = 2;
  // Clusters whose representative cell lies this close to a blacklisted point are ignored.
  double blacklist_radius = 0.5;        // m
  // Clusters whose representative lies this close to the robot are ignored: a frontier that near
  // is one the forward-looking laser cannot see from here (under or behind the robot), and going
  // to it would end at once without revealing anything. Reached later from elsewhere, the robot
  // arrives facing it.
  double min_target_distance = 0.5;     // m
  // The area to explore, in map metres, when it is known: clusters whose representative lies
  // outside are not targets. The paper's maze result (Fig. 7(d)) knows the maze's boundary.
  // Predictions reach beyond outer walls (its Fig. 7(e)); where they cover a stretch of wall not
  // yet seen, the planner finds a way out through them, and each prediction out there opens new
  // frontiers to predict for. Unset: unbounded.
  std::optional<Eigen::AlignedBox2d> area;
  // What a cluster is worth, in metres of path cost: gain_weight times its frontier length, at most
  // gain_cap_m. A long opening beats a pocket beside a desk that is a little nearer.
  double gain_weight = 1.0;
  double gain_cap_m = 2.0;
  // Hysteresis: the cluster that still holds the current goal (a cell within keep_goal_radius of
  // ExploreRequest::current_goal) is worth keep_goal_bonus more, so the robot does not turn back and
  // forth between frontiers at nearly the same cost each time it replans.
  double keep_goal_bonus = 3.0;   // m
  double keep_goal_radius = 1.0;  // m
  // Way in (skip-predicted): predicted cells are not verified, and a predicted wall may stand where
  // the building opens. A second search goes on from the traversable space through predicted and
  // unknown cells at way_in_cost_factor times their length, and when it reaches a cluster that is
  // not covered, the target is where that way leaves the traversable space. 0: off. While there is
  // a frontier to go to, a way in is taken only if it costs less than that frontier's path cost
  // divided by way_in_premium.
  // Exits within way_in_tried_radius of one the caller already reached are not offered again, nor
  // ways through the unverified cells that close to it.
  double way_in_cost_factor = 0.0;
  double way_in_premium = 3.0;
  double way_in_tried_radius = 1.5;  // m
};

// Whether an unknown cell (of the built map's lattice) is covered by an accepted hypothesis.
using CoveredPredicate = std::function<bool(const Eigen::Vector2i& cell)>;

struct ExploreRequest {
  Eigen::Vector2d robot_position = Eigen::Vector2d::Zero();
  CoveredPredicate covered;                // used in kSkipPredicted; empty: nothing is covered
  // Covered cells predicted occupied (kSkipPredicted). The unknown space behind a predicted wall,
  // such as an obstacle's interior, is not what the frontier would reveal, and nothing predicts
  // it; it must not count against the frontier. Empty: no walls.
  CoveredPredicate predicted_wall;
  std::vector<Eigen::Vector2d> blacklist;  // goals the caller gave up on (e.g. blocked on the way)
  // Cells an accepted hypothesis predicts and the built map has not decided (kSkipPredicted).
  // When the explorer plans on the map with the predictions merged in, they look mapped, yet they
  // are the frontier's unexplored surroundings as much as the unknown cells are: the covered
  // fraction counts them, so that an unknown gap between predictions is skipped, not visited.
  // Empty: the planning map's unknown cells are all there is.
  CoveredPredicate predicted;
  // The target the robot is driving to (ExploreOptions::keep_goal_bonus); unset: none.
  std::optional<Eigen::Vector2d> current_goal;
  // Way-in exits the robot has reached (ExploreOptions::way_in_cost_factor).
  std::vector<Eigen::Vector2d> tried_way_ins;
};

struct ExploreTarget {
  FrontierCluster cluster;
  Eigen::Vector2i cell{0, 0};          // representative: the reachable cluster cell nearest the centroid
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // its centre
  double path_length = 0.0;            // m along the cell path
  std::vector<Eigen::Vector2d> path;   // simplified waypoints from the robot to 'position'
  // 'position' is not on the cluster but where the way to it leaves the traversable space
  // (ExploreOptions::way_in_cost_factor); the caller reports it in tried_way_ins once reached.
  bool way_in = false;
  double cost = 0.0;  // path cost to 'position' (for a way in, on to the cluster), m
};

struct ExploreDecision {
  // Empty when exploration is done: no frontier cluster is left that is reachable, inside the
  // area, not skipped and not blacklisted.
  std::optional<ExploreTarget> target;
  int clusters = 0;          // frontier clusters found
  int skipped = 0;           // covered by predictions
  int unreachable = 0;       // no traversable cell reached by the search
  int blacklisted = 0;
  int too_close = 0;         // within min_target_distance of the robot
  int outside_area = 0;      // outside ExploreOptions::area
  int unranked = 0;          // beyond where the search stopped: none of them could have been chosen
  bool start_blocked = false;     // the robot's own position could not be left: nothing is reachable
  bool search_truncated = false;  // the search hit its node cap: farther clusters were not ranked
  std::size_t expanded_nodes = 0; // cells the path search settled

  bool done() const { return !target.has_value(); }
};

ExploreDecision SelectNextTarget(const OccupancyGrid& grid, const ExploreRequest& request,
                                 const ExploreOptions& options = {});

// SelectNextTarget on 'merged' (the built map with predictions written in), and on 'built' alone
// when that leaves only unreachable frontiers: predicted walls can close a way the robot's own map
// leaves open, and never end an exploration on their own.
ExploreDecision SelectNextTargetOnMerged(const OccupancyGrid& merged, const OccupancyGrid& built,
                                         const ExploreRequest& request, const ExploreOptions& options = {});

// Visible for testing: the fraction of a frontier's unexplored surroundings that predictions
// cover. The cells within 'radius' of the cluster, reached from its cells through unknown cells
// and through request.predicted ones, are counted, and those for which request.covered holds are
// hits; nullopt when none are counted. Cells 'grid' has observed but not decided (unknown to the
// explorer, cell_class.hpp) are counted only where request.predicted holds, and otherwise passed
// through: around the ragged end of the laser's reach such cells dominate, and counted as
// uncovered no frontier there could ever look covered, while counted as covered they would skip
// frontiers nothing predicted. Cells for which request.predicted_wall holds, and cells within
// 'seal_cells' of such a cell or of an occupied one, are counted but not passed through
// (ExploreOptions::wall_seal_cells).
std::optional<double> CoveredFraction(const OccupancyGrid& grid, const FrontierCluster& cluster,
                                      const ExploreRequest& request, double radius, int seal_cells = 0,
                                      const CellClassOptions& classes = {});

}  // namespace pslam
