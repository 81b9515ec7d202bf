#pragma once
// The skip-predicted run of `pslam experiment explore --generated FAMILY --seed S --threads 1` on
// one generated floor plan, for tests that replay a case the population benchmark found.
#include <cstdint>

#include "pslam/experiment/exploration_run.hpp"
#include "pslam/sim/floorplan.hpp"

namespace pslam::testing {

inline ExplorationOptions SkipRunOptions(const FloorPlan& plan, std::uint64_t seed, double time_limit_s) {
  ExplorationOptions options = DefaultExplorationOptions();
  options.slam.filter.seed = options.simulator.seed = seed;
  options.slam.filter.threads = 1;
  options.slam.predictor.similarity_threshold = 0.6;
  options.slam.predict = true;
  options.explore.mode = ExploreMode::kSkipPredicted;
  options.explore.area = plan.world.Extent();
  options.time_limit_s = time_limit_s;
  return options;
}

}  // namespace pslam::testing
