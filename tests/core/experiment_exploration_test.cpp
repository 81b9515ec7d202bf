// The whole P-SLAM loop in the paper's square maze (ExplorationRun: simulator, particle filter,
// predictor, explorer, follower): what must hold at every step, and what a short run must achieve.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <iterator>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "pslam/experiment/exploration_run.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/sim/world.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

namespace fs = std::filesystem;

std::string WorldYaml(const std::string& name) {
  return (fs::path(PSLAM_SOURCE_DIR) / "core" / "worlds" / (name + ".yaml")).string();
}

// Fewer particles than the default: the checks are about the loop, not the filter's accuracy.
ExplorationOptions ShortRunOptions(ExploreMode mode, double time_limit_s) {
  ExplorationOptions options = DefaultExplorationOptions();
  options.slam.filter.particles = 10;
  options.slam.predictor.similarity_threshold = 0.6;  // the paper's simulations (Sec. V-A)
  options.explore.mode = mode;
  options.time_limit_s = time_limit_s;
  return options;
}

// The nearest frontier first, with no worth and no hysteresis: the route on which some of the cases
// below were found. Where the robot is when a prediction is made decides what it predicts.
ExplorationOptions NearestFirst(ExplorationOptions options) {
  options.explore.gain_weight = 0.0;
  options.explore.keep_goal_bonus = 0.0;
  return options;
}

// Cells of 'cells' that 'map' has observed.
int KnownCount(const std::vector<HypothesisCell>& cells, const OccupancyGrid& map) {
  int known = 0;
  for (const HypothesisCell& c : cells) known += map.IsKnown(c.cell.x(), c.cell.y());
  return known;
}

bool ByCell(const HypothesisCell& a, const HypothesisCell& b) {
  return std::tie(a.cell.x(), a.cell.y()) < std::tie(b.cell.x(), b.cell.y());
}

// 'hypotheses' with their cells sorted, for set differences.
std::vector<Hypothesis> SortedByCell(std::vector<Hypothesis> hypotheses) {
  for (Hypothesis& h : hypotheses) std::sort(h.cells.begin(), h.cells.end(), ByCell);
  return hypotheses;
}

// Cells known both in a particle's map and in its hypothesis map: predictions that were not given
// way to what the particle observed.
int OverlapInParticle(const Particle& p) {
  int overlap = 0;
  const CellBox box = p.hypothesis.KnownBounds();
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) overlap += p.hypothesis.IsKnown(x, y) && p.map.IsKnown(x, y);
  }
  return overlap;
}

class MazeRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::optional<Pose2D> start = ReadStartPose(WorldYaml("maze"));
    ASSERT_TRUE(start.has_value());
    start_ = *start;
  }
  World world_ = LoadWorld(WorldYaml("maze"));
  Pose2D start_;
};

TEST_F(MazeRunTest, HypothesesOnlyEverCoverUnexploredCellsAndSomeMatchTheTruth) {
  ExplorationRun run(world_, start_, ShortRunOptions(ExploreMode::kSkipPredicted, 110.0));
  int updates = 0, checked = 0;
  bool some_shrank = false;
  std::vector<Hypothesis> before;  // the hypotheses as the previous step left them
  while (!run.done()) {
    const ExplorationStep step = run.Step();
    // Validation removes explored parts: a hypothesis only ever loses cells the best map (the one
    // P-SLAM judged on in this step) has observed, and cells near those (within the local
    // refutation radius) when what was observed contradicts it. The best particle may change
    // later, so this is checked at the step, not at the end.
    const double radius_cells = run.slam().options().judge.local_refutation_radius_m /
                                run.slam().options().filter.resolution;
    const std::vector<Hypothesis> after = SortedByCell(run.slam().hypotheses());
    for (std::size_t i = 0; i < before.size(); ++i) {
      const Hypothesis& now = after[i];
      ASSERT_LE(now.cells.size(), before[i].cells.size());
      if (now.cells.size() == before[i].cells.size()) continue;
      some_shrank = true;
      std::vector<HypothesisCell> lost;
      std::set_difference(before[i].cells.begin(), before[i].cells.end(), now.cells.begin(), now.cells.end(),
                          std::back_inserter(lost), ByCell);
      const OccupancyGrid& map = run.slam().filter().best().map;
      std::vector<Eigen::Vector2i> observed;
      for (const HypothesisCell& c : lost) {
        if (map.IsKnown(c.cell.x(), c.cell.y())) observed.push_back(c.cell);
      }
      for (const HypothesisCell& c : lost) {
        if (map.IsKnown(c.cell.x(), c.cell.y())) continue;
        ASSERT_TRUE(std::any_of(observed.begin(), observed.end(), [&](const Eigen::Vector2i& o) {
          return (o - c.cell).cast<double>().norm() <= radius_cells;
        })) << "hypothesis " << now.id << " lost a cell far from any it lost to observation at t = " << run.time();
      }
    }
    before = after;
    if (!step.slam.filter.updated || ++updates % 4 != 0) continue;
    ++checked;
    const OccupancyGrid& best = run.slam().filter().best().map;
    // V of eq. 20 at the level P-SLAM reports: a pending hypothesis keeps only unexplored cells.
    for (const Hypothesis& h : run.slam().hypotheses()) {
      if (h.status != Hypothesis::Status::kPending) continue;
      ASSERT_EQ(KnownCount(h.cells, best), 0) << "hypothesis " << h.id << " at t = " << run.time();
    }
    // ... and at the level that weighs the particles (S2 of eq. 22).
    for (const Particle& p : run.slam().filter().particles()) ASSERT_EQ(OverlapInParticle(p), 0) << "t = " << run.time();
  }
  ASSERT_GT(checked, 10);
  ASSERT_FALSE(run.accepted_hypotheses().empty()) << "no hypothesis in " << run.time() << " s";

  // The merged map never overrides a decided cell: predictions fill unknown and undecided ones.
  const OccupancyGrid& best = run.slam().filter().best().map;
  const OccupancyGrid merged = run.slam().MergedMap();
  const CellClassifier classify(run.slam().options().predictor.states);
  const CellBox box = best.KnownBounds();
  int filled_undecided = 0;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      if (!best.IsKnown(x, y) || merged.At(x, y) == best.At(x, y)) continue;
      ASSERT_EQ(classify(best.At(x, y)), CellState::kUncertain) << x << ", " << y;
      ASSERT_TRUE(run.slam().IsCovered({x, y}));
      ++filled_undecided;
    }
  }
  EXPECT_GT(filled_undecided, 0);

  // The robot has explored into some hypothesis.
  EXPECT_TRUE(some_shrank);

  // At least one prediction is right about the real maze (Psi >= 0.5 against the true world). The
  // SLAM map frame starts as the world frame; each prediction is moved by the SLAM error of its
  // time, as the experiment does, since a few centimetres of drift are worth a cell of Psi.
  const OccupancyGrid truth = world_.ToGrid();
  double best_psi = 0.0;
  for (std::size_t i = 0; i < run.accepted_hypotheses().size(); ++i) {
    const auto in_world = TransformCells(run.accepted_hypotheses()[i].cells, run.accepted_map_to_world()[i],
                                         truth.resolution());
    best_psi = std::max(best_psi, PredictionSimilarity(in_world, truth));
  }
  EXPECT_GE(best_psi, 0.5);

  const ExplorationSummary summary = run.Summary();
  EXPECT_EQ(summary.collisions, 0u);
  EXPECT_GT(summary.distance_m, 5.0);
  EXPECT_LT(summary.mean_position_error_m, 0.3);
}

// Whether a wall lies within 'reach' cells of the control point P1 of accepted hypothesis 'index':
// one the best map has observed, and one predicted by an earlier accepted hypothesis for which
// 'counts' holds (as P-SLAM holds it now).
struct WallsNearP1 {
  bool observed = false;
  bool predicted = false;
};
WallsNearP1 WallsNearControlPoint(const ExplorationRun& run, std::size_t index,
                                  const std::function<bool(const Hypothesis&)>& counts, int reach = 3) {
  const OccupancyGrid& best = run.slam().filter().best().map;
  OccupancyGrid predicted_walls(best.resolution());
  for (std::size_t j = 0; j < index; ++j) {
    if (!counts(run.slam().hypotheses()[j])) continue;
    for (const HypothesisCell& c : run.accepted_hypotheses()[j].cells) {
      if (c.occupied) predicted_walls.MutableAt(c.cell.x(), c.cell.y()) = 0;
    }
  }
  WallsNearP1 near;
  const Eigen::Vector2i p1 = best.WorldToCell(run.accepted_hypotheses()[index].target_control_point);
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const Eigen::Vector2i c = p1 + Eigen::Vector2i(dx, dy);
      near.observed = near.observed || (best.IsKnown(c.x(), c.y()) && best.Probability(c.x(), c.y()) > 0.5f);
      near.predicted = near.predicted || predicted_walls.IsKnown(c.x(), c.y());
    }
  }
  return near;
}

// Steps 'run' until it has accepted a hypothesis predicted from predicted structure, or is done:
// one whose P1 has no observed wall near it but a wall that an earlier hypothesis for which
// 'counts' holds predicted, and none that the others predicted. Returns how many it accepted.
int StepUntilAChainedPrediction(ExplorationRun& run,
                                const std::function<bool(const Hypothesis&)>& counts = [](const Hypothesis&) {
                                  return true;
                                }) {
  const auto others = [&counts](const Hypothesis& h) { return !counts(h); };
  std::size_t seen = 0;
  while (!run.done()) {
    run.Step();
    for (; seen < run.accepted_hypotheses().size(); ++seen) {
      const WallsNearP1 near = WallsNearControlPoint(run, seen, counts);
      if (!near.observed && near.predicted && !WallsNearControlPoint(run, seen, others).predicted) {
        return static_cast<int>(seen) + 1;
      }
    }
  }
  return -1;
}

// Skip-predicted exploration plans on the merged map, and its targets lie at the edge of what is
// predicted: the predictor reads the same map, so a prediction can carry on from predicted walls.
TEST_F(MazeRunTest, PredictionsCarryOnFromPredictedWallsWhenPlanningOnTheMergedMap) {
  // The filter as it mapped when this case was found: with scan matching leaning on the simulated
  // wheels (SetMatchPrior) no chained prediction comes within 400 s.
  ExplorationOptions merged = NearestFirst(ShortRunOptions(ExploreMode::kSkipPredicted, 400.0));
  SetMatchPrior(merged.slam.filter, 0.0);
  ExplorationRun run(world_, start_, merged);
  ASSERT_TRUE(run.slam().options().predict_on_merged_map);
  const int accepted = StepUntilAChainedPrediction(run);
  EXPECT_GT(accepted, 0) << "none in " << run.time() << " s";

  // Planning on the built map, the predictor reads it too, and never sees a predicted wall.
  ExplorationOptions options = merged;
  options.plan_on_merged_map = false;
  ExplorationRun on_built(world_, start_, options);
  ASSERT_FALSE(on_built.slam().options().predict_on_merged_map);
  EXPECT_EQ(StepUntilAChainedPrediction(on_built), -1);
  EXPECT_FALSE(on_built.accepted_hypotheses().empty());
}

// ... but not from a hypothesis below predict_from_psi that observation has not confirmed.
TEST_F(MazeRunTest, PredictionsDoNotBuildOnWeakHypotheses) {
  ExplorationOptions options = ShortRunOptions(ExploreMode::kSkipPredicted, 400.0);
  options.slam.filter.seed = options.simulator.seed = 1;  // a run that builds on one within 400 s
  // ... with the filter as it mapped when this case was found: since beams that graze a wall stop
  // short and the odometry's scale is learned, this run's and seeds 2-10's predictions never build
  // on a weak hypothesis within 400-700 s, so the case would not arise (nor, since, with scan
  // matching leaning on the simulated wheels, nor with hypotheses withdrawn around what
  // contradicts them).
  options.slam.filter.insert.grazing_stop = false;
  options.slam.filter.odometry_calibration.enabled = false;
  SetMatchPrior(options.slam.filter, 0.0);
  options.slam.judge.local_refutation_radius_m = 0.0;
  const double bar = options.slam.predict_from_psi;
  ASSERT_GT(bar, options.slam.predictor.similarity_threshold);
  const auto weak = [bar](const Hypothesis& h) { return h.psi < bar && h.status != Hypothesis::Status::kConfirmed; };
  ExplorationRun run(world_, start_, options);
  EXPECT_EQ(StepUntilAChainedPrediction(run, weak), -1);
  EXPECT_TRUE(std::any_of(run.accepted_hypotheses().begin(), run.accepted_hypotheses().end(),
                          [bar](const Hypothesis& h) { return h.psi < bar; }));

  // Without the bar the same run does build on one.
  ExplorationOptions any = options;
  any.slam.predict_from_psi = 0.0;
  ExplorationRun unguarded(world_, start_, any);
  EXPECT_GT(StepUntilAChainedPrediction(unguarded, weak), 0);
}

TEST_F(MazeRunTest, SameSeedSameRun) {
  const ExplorationOptions options = ShortRunOptions(ExploreMode::kSkipPredicted, 70.0);
  ExplorationRun a(world_, start_, options), b(world_, start_, options);
  a.Run();
  b.Run();
  const ExplorationSummary sa = a.Summary(), sb = b.Summary();
  EXPECT_EQ(sa.scans, sb.scans);
  EXPECT_EQ(sa.targets, sb.targets);
  EXPECT_DOUBLE_EQ(sa.distance_m, sb.distance_m);
  EXPECT_DOUBLE_EQ(sa.mean_position_error_m, sb.mean_position_error_m);
  ASSERT_EQ(a.accepted_hypotheses().size(), b.accepted_hypotheses().size());
  for (std::size_t i = 0; i < a.accepted_hypotheses().size(); ++i) {
    EXPECT_EQ(a.accepted_hypotheses()[i].cells.size(), b.accepted_hypotheses()[i].cells.size());
  }
  const Pose2D pa = a.slam().filter().best().pose, pb = b.slam().filter().best().pose;
  EXPECT_DOUBLE_EQ(pa.x, pb.x);
  EXPECT_DOUBLE_EQ(pa.y, pb.y);
}

// Paths planned for a robot of 5 cm radius hug the walls the real 25 cm disc cannot pass, and with
// the obstacle stop off nothing saves it: contacts are certain. A contact must make the robot back
// off and try again; only a second one soon after gives the target up, and exploring goes on.
TEST_F(MazeRunTest, AContactBacksOffAndOnlyARepeatedOneGivesTheTargetUp) {
  ExplorationOptions options = ShortRunOptions(ExploreMode::kFullCoverage, 90.0);
  options.slam.predict = false;
  options.explore.planner.robot_radius = 0.05;
  options.explore.planner.inflation_margin = 0.0;
  options.explore.planner.wall_cost_weight = 0.0;
  options.obstacle_stop.stop_distance = 0.0;
  ExplorationRun run(world_, start_, options);
  int contacts = 0, backing_steps = 0;
  std::optional<double> backing_since;
  while (!run.done()) {
    const ExplorationStep step = run.Step();
    if (step.collided) {
      ++contacts;
      // A contact while backing off ends the back-off: the robot plans from where it stands.
      const bool backing = backing_since && run.time() - *backing_since < options.back_off_s;
      backing_since = backing ? std::nullopt : std::optional<double>(run.time());
    }
    if (backing_since && run.time() - *backing_since < options.back_off_s - 0.2) {
      ASSERT_LT(step.command.linear, 0.0) << "t = " << run.time();
      EXPECT_EQ(step.command.angular, 0.0);
      ++backing_steps;
    }
  }
  ASSERT_GE(contacts, 2);
  EXPECT_GT(backing_steps, 0);
  const ExplorationSummary summary = run.Summary();
  EXPECT_GE(summary.given_up, 1);
  EXPECT_LT(summary.given_up, contacts);  // a first contact gives nothing up
  EXPECT_EQ(run.state(), ExplorationState::kTimeLimit);  // nor ends exploring early
}

TEST_F(MazeRunTest, ARunLeftWithOnlyGivenUpFrontiersIsStuckNotExplored) {
  ExplorationOptions options = ShortRunOptions(ExploreMode::kFullCoverage, 600.0);
  options.slam.predict = false;
  options.obstacle_stop.stop_distance = 3.0;  // held wherever a wall is ahead: targets are given up
  ExplorationRun run(world_, start_, options);
  run.Run();
  ASSERT_GT(run.Summary().given_up, 0);
  EXPECT_NE(run.state(), ExplorationState::kExplored);
}

TEST_F(MazeRunTest, PlainRbpfMakesNoPredictionsAndStopsAtTheTimeLimit) {
  ExplorationOptions options = ShortRunOptions(ExploreMode::kFullCoverage, 20.0);
  options.slam.predict = false;
  ExplorationRun run(world_, start_, options);
  run.Run();
  EXPECT_EQ(run.state(), ExplorationState::kTimeLimit);
  EXPECT_NEAR(run.time(), 20.0, 0.5);
  EXPECT_TRUE(run.accepted_hypotheses().empty());
  EXPECT_GT(run.Summary().targets, 0);
  EXPECT_TRUE(run.Step().events.empty());  // a finished run does nothing
}

TEST_F(MazeRunTest, TheMappedTrajectoryPairsEveryScansTruthWithTheMapsPose) {
  ExplorationOptions options = ShortRunOptions(ExploreMode::kFullCoverage, 30.0);
  options.slam.predict = false;
  ExplorationRun run(world_, start_, options);
  run.Run();
  const std::vector<MappedPose> poses = run.MappedTrajectory();
  ASSERT_EQ(poses.size(), run.Summary().scans);
  EXPECT_NEAR((poses.front().truth.translation() - start_.translation()).norm(), 0.0, 0.05);
  double travelled = 0.0, off = 0.0;
  for (std::size_t i = 1; i < poses.size(); ++i) {
    travelled += (poses[i].truth.translation() - poses[i - 1].truth.translation()).norm();
    off = std::max(off, (poses[i].truth.translation() - poses[i].in_map.translation()).norm());
  }
  EXPECT_GT(travelled, 2.0);
  EXPECT_LT(off, 0.3) << "the maze's map frame starts at the world's and a short run stays near it";
  // The map's poses are the filter's corrected trajectory, not the truth copied.
  EXPECT_GT(std::abs(poses.back().in_map.x - poses.back().truth.x) + std::abs(poses.back().in_map.y - poses.back().truth.y),
            1e-6);
}

}  // namespace
}  // namespace pslam
