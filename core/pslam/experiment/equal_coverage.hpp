#pragma once
// Exploration time compared fairly: at equal coverage. A skip-predicted run is shorter for a reason
// only if it ends up having mapped or predicted as much of the world as full coverage did; one
// that stops early has saved nothing. Coverage counts the free cells the robot can reach from its
// start (4-connected free space), so pockets nobody could enter do not count against any run.
#include <Eigen/Core>
#include <functional>
#include <utility>
#include <vector>

#include "pslam/experiment/exploration_run.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

// The world's free cells 4-connected to 'start' (free in the grid), nothing else: the reference
// for MappedOrPredictedFraction.
OccupancyGrid ReachableFreeCells(const World& world, const Eigen::Vector2d& start);

// The share of 'reachable' (ReachableFreeCells) that the run's best map knows or its merged
// predictions, moved into the world frame, cover now.
double MappedOrPredictedNow(const ExplorationRun& run, const OccupancyGrid& reachable);

// Coverage over a run: (simulated time, MappedOrPredictedNow) samples in time order.
struct CoverageTrace {
  std::vector<std::pair<double, double>> samples;
  double Final() const { return samples.empty() ? 0.0 : samples.back().second; }
  // The first sampled time at which coverage reached 'fraction'; NaN if it never did.
  double TimeToReach(double fraction) const;
};

// Steps the run to its end, sampling coverage every 'period_s' simulated seconds and at the end.
// 'on_step' (may be empty) is called after every step, e.g. for a progress line.
CoverageTrace RunRecordingCoverage(ExplorationRun& run, const OccupancyGrid& reachable, double period_s,
                                   const std::function<void()>& on_step = {});

struct EqualCoverageSaving {
  double target = 0.0;       // coverage both runs are timed to: full coverage's final one minus the tolerance
  double full_time_s = 0.0;  // when full coverage first reached it
  double skip_time_s = 0.0;  // when skip-predicted first reached it; NaN if never
  bool skip_reached = false;
  // (full - skip) / full when skip reached the target, else 0: a run that stops early saves nothing.
  double saved_fraction = 0.0;
};
// 'tolerance' (a share of the reachable free area) absorbs the last scraps full coverage maps and
// skip-predicted mode has no reason to visit.
EqualCoverageSaving CompareAtEqualCoverage(const CoverageTrace& full, const CoverageTrace& skip, double tolerance);

}  // namespace pslam
