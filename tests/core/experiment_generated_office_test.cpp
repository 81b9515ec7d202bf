// P-SLAM in a building it was never tuned on: a short skip-predicted run in a generated office
// makes hypotheses, and they match the true world (Psi >= 0.4, the paper's "reasonable quality").
// Coverage sampled along the run only grows where it should: from the start until the end.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pslam/experiment/equal_coverage.hpp"
#include "pslam/experiment/exploration_run.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/sim/floorplan.hpp"

namespace pslam {
namespace {

TEST(GeneratedOfficeRunTest, ShortRunMakesAHypothesisThatMatchesTheTruth) {
  const FloorPlan plan = GenerateFloorPlan(FloorPlanFamily::kOffice, 2);
  ExplorationOptions options = DefaultExplorationOptions();
  options.slam.filter.particles = 10;  // the check is about the predictor, not the filter's accuracy
  options.slam.predictor.similarity_threshold = 0.6;
  options.explore.mode = ExploreMode::kSkipPredicted;
  options.explore.area = plan.world.Extent();
  options.time_limit_s = 300.0;
  ExplorationRun run(plan.world, plan.start, options);
  const OccupancyGrid reachable = ReachableFreeCells(plan.world, plan.start.translation());
  const CoverageTrace trace = RunRecordingCoverage(run, reachable, 20.0);
  ASSERT_FALSE(run.accepted_hypotheses().empty()) << plan.description;

  const OccupancyGrid truth = plan.world.ToGrid();
  int matching = 0;
  for (std::size_t i = 0; i < run.accepted_hypotheses().size(); ++i) {
    const auto cells = TransformCells(run.accepted_hypotheses()[i].cells, run.accepted_map_to_world()[i],
                                      options.slam.filter.resolution);
    const double psi = PredictionSimilarity(cells, truth);
    matching += std::isfinite(psi) && psi >= 0.4;
  }
  EXPECT_GT(matching, 0) << run.accepted_hypotheses().size() << " hypotheses, none matching the truth";

  ASSERT_GE(trace.samples.size(), 2u);
  EXPECT_GT(trace.Final(), trace.samples.front().second);
  EXPECT_LE(trace.Final(), 1.0);
  EXPECT_DOUBLE_EQ(trace.samples.back().first, run.time());
}

}  // namespace
}  // namespace pslam
