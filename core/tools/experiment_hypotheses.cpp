// `pslam experiment hypotheses`: the office simulation of the paper (Sec. V-A2, Fig. 10). P-SLAM
// explores every accessible region with full coverage, so that the robot eventually sees what it
// predicted; then each hypothesis is scored with Psi (eq. 5) against the final built map, as the
// paper does (also exactly as the paper took it, see kPaperResolution), and against the true
// world, which the paper could not do (each moved into the world frame by the SLAM error at the
// time it was accepted, so that a later slip of the map does not count against it). The paper had
// 56 hypotheses covering 30 % of the explored area, 36 of them (64 %) with Psi >= 0.4, mean 0.51.
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "experiment_common.hpp"
#include "pslam/experiment/equal_coverage.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/experiment/observable_truth.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam experiment hypotheses [--world FILE.yaml] [--start X,Y,THETA] [--mode full|skip]\n"
    "                                   [--json OUT] [--save PREFIX] [--quiet] [options]\n"
    "  Explores the world with P-SLAM (default: full coverage, core/worlds/office.yaml) and scores every\n"
    "  hypothesis with Psi against the final built map and against the true world.\n"
    "  --save PREFIX writes PREFIX (built map) and PREFIX_merged (.pgm/.yaml/.png).\n";

struct PsiSummary {
  int scored = 0;           // hypotheses with at least one cell the reference knows
  int at_least_04 = 0;      // Psi >= 0.4, the paper's "reasonable-quality" mark
  double mean = 0.0;
  double min = 0.0, max = 0.0;
  std::vector<int> histogram = std::vector<int>(10, 0);  // Psi in [0, 0.1), ..., [0.9, 1.0]
};

PsiSummary Summarize(const std::vector<double>& values) {
  PsiSummary s;
  s.min = std::numeric_limits<double>::infinity();
  s.max = -std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    ++s.scored;
    s.at_least_04 += v >= 0.4;
    sum += v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
    ++s.histogram[static_cast<std::size_t>(std::clamp(static_cast<int>(v * 10.0), 0, 9))];
  }
  if (s.scored == 0) s.min = s.max = std::numeric_limits<double>::quiet_NaN();
  s.mean = s.scored ? sum / s.scored : std::numeric_limits<double>::quiet_NaN();
  return s;
}

std::string SummaryJson(const PsiSummary& s) {
  std::vector<double> histogram(s.histogram.begin(), s.histogram.end());
  return JsonObject({{"scored", JsonNumber(s.scored)},
                     {"at_least_0_4", JsonNumber(s.at_least_04)},
                     {"fraction_at_least_0_4", JsonNumber(s.scored ? static_cast<double>(s.at_least_04) / s.scored : 0.0)},
                     {"mean", JsonNumber(s.mean)},
                     {"min", JsonNumber(s.min)},
                     {"max", JsonNumber(s.max)},
                     {"histogram_0_1", JsonArray(histogram)}});
}

// Eq. 5 exactly as the paper took it: on its 0.1 m cells (our 5 cm ones pooled 2 x 2), with no
// tolerance. Our Psi, a one-cell tolerance on 5 cm cells, is the more lenient of the two.
constexpr double kPaperResolution = 0.1;
const SimilarityOptions kNoTolerance{CellStateThresholds{}, 0};

struct HypothesesResult {
  double time_s = 0.0;
  bool time_limit = false;
  int count = 0;
  double truth_mean = 0.0, truth_share = 0.0, final_share = 0.0;  // share: Psi >= 0.4
  std::string json;
};

// One P-SLAM exploration of 'world', its hypotheses scored and printed.
HypothesesResult RunOneWorld(const WorldChoice& world, ExplorationOptions options, const std::string& mode,
                             const std::optional<std::string>& save_prefix, ProgressLine& progress) {
  options.slam.predict = true;
  options.explore.mode = mode == "skip" ? ExploreMode::kSkipPredicted : ExploreMode::kFullCoverage;
  ExplorationRun run(world.world, world.start, options);
  const ExplorationSummary summary = RunExplorationWithProgress(run, "P-SLAM " + mode, progress);
  const OccupancyGrid truth = world.world.ToGrid();
  const OccupancyGrid observable =
      ObservableTruth(world.world, ReachableFreeCells(world.world, world.start.translation()));
  const OccupancyGrid& built = run.slam().filter().best().map;

  // Hypotheses overlap (targets a few metres apart predict much the same space): the predicted
  // area is that of the union of their cells; the sum of their areas is reported beside it.
  double summed_area = 0.0;
  OccupancyGrid predicted_cells(built.resolution());
  std::vector<double> psi_final, psi_final_paper_cells, psi_truth, psi_observable, psi_search;
  const int pool = std::max(1, static_cast<int>(std::lround(kPaperResolution / built.resolution())));
  const OccupancyGrid pooled_built = PoolGrid(built, pool);
  const std::vector<std::vector<HypothesisCell>> in_world = AcceptedCellsInWorld(run);
  for (std::size_t i = 0; i < run.accepted_hypotheses().size(); ++i) {
    const Hypothesis& h = run.accepted_hypotheses()[i];
    summed_area += h.area_m2;
    for (const HypothesisCell& c : h.cells) predicted_cells.MutableAt(c.cell.x(), c.cell.y()) = 0;
    psi_final.push_back(PredictionSimilarity(h.cells, built));
    psi_final_paper_cells.push_back(PredictionSimilarity(PoolCells(h.cells, pool), pooled_built, kNoTolerance));
    psi_truth.push_back(PredictionSimilarity(in_world[i], truth));
    psi_observable.push_back(PredictionSimilarity(in_world[i], observable));
    psi_search.push_back(h.psi);
  }
  const double predicted_area = KnownArea(predicted_cells);
  const double covered_area = KnownArea(built);
  const double fraction = covered_area > 0.0 ? predicted_area / covered_area : 0.0;
  const PsiSummary final_summary = Summarize(psi_final), truth_summary = Summarize(psi_truth);
  const PsiSummary paper_cells_summary = Summarize(psi_final_paper_cells);
  const JudgeAgreement agreement = CountJudgedAsTruth(run, psi_truth);

  std::printf("world %s, start (%.2f, %.2f, %.3f), seed %llu, %d particles, similarity threshold %.2f, %s coverage\n",
              world.path.c_str(), world.start.x, world.start.y, world.start.theta,
              static_cast<unsigned long long>(options.slam.filter.seed), options.slam.filter.particles,
              options.slam.predictor.similarity_threshold, mode.c_str());
  std::printf("exploration              %.1f s simulated, %.1f m, %s, %zu collisions, mean position error %.3f m\n",
              summary.time_s, summary.distance_m, ExplorationStateName(summary.state), summary.collisions,
              summary.mean_position_error_m);
  std::printf("hypotheses               %d accepted (%d confirmed, %d refuted, %d expired, rest pending) "
              "of %d predictions; %llu below the threshold, %llu ambiguous\n",
              summary.hypotheses, summary.slam.confirmed, summary.slam.refuted, summary.slam.expired,
              summary.slam.predictions_made, static_cast<unsigned long long>(summary.slam.outcomes.below_threshold),
              static_cast<unsigned long long>(summary.slam.outcomes.ambiguous));
  std::printf("judge vs true world      %d of %d confirmed/refuted hypotheses agree with Psi vs truth >= %.2f\n",
              agreement.as_truth, agreement.judged, options.slam.judge.confirm_psi);
  std::printf("predicted / covered area %.1f m^2 / %.1f m^2 = %.1f %%  (paper: 605.76 / ~2000 m^2 = 30 %%); "
              "summed over hypotheses %.1f m^2\n",
              predicted_area, covered_area, 100.0 * fraction, summed_area);
  std::printf("%-22s %6s %8s %8s %6s %6s %6s\n", "Psi of the hypotheses", "scored", ">= 0.4", "share", "mean",
              "min", "max");
  const auto row = [](const char* name, const PsiSummary& s) {
    std::printf("%-22s %6d %8d %7.1f%% %6.3f %6.3f %6.3f\n", name, s.scored, s.at_least_04,
                s.scored ? 100.0 * s.at_least_04 / s.scored : 0.0, s.mean, s.min, s.max);
  };
  row("vs final built map", final_summary);
  char paper_cells_name[40];
  std::snprintf(paper_cells_name, sizeof paper_cells_name, "  eq. 5 on %.2f m cells", built.resolution() * pool);
  row(paper_cells_name, paper_cells_summary);
  row("vs true world", truth_summary);
  row("  what can be seen", Summarize(psi_observable));
  std::printf("paper (vs final map)   %6d %8d %7.1f%% %6.3f %6.3f %6.3f\n", 56, 36, 64.3, 0.51, 0.10, 0.86);
  std::printf("distribution (Fig. 10)  Psi bin:    ");
  for (int b = 0; b < 10; ++b) std::printf(" %3.1f", 0.1 * b);
  std::printf("\n  hypotheses vs final map:          ");
  for (const int n : final_summary.histogram) std::printf(" %3d", n);
  std::printf("\n  hypotheses vs true world:         ");
  for (const int n : truth_summary.histogram) std::printf(" %3d", n);
  std::printf("\n");

  if (save_prefix && !save_prefix->empty()) {
    SaveMap(built, *save_prefix);
    SaveMap(run.slam().MergedMap(), *save_prefix + "_merged");
    SaveMappingTrajectory(MappingTrajectoryPath(*save_prefix), run.MappedTrajectory());
  }
  HypothesesResult result;
  result.time_s = summary.time_s;
  result.time_limit = summary.state == ExplorationState::kTimeLimit;
  result.count = summary.hypotheses;
  result.truth_mean = truth_summary.mean;
  const auto share = [](const PsiSummary& p) {
    return p.scored ? static_cast<double>(p.at_least_04) / p.scored : std::numeric_limits<double>::quiet_NaN();
  };
  result.truth_share = share(truth_summary);
  result.final_share = share(final_summary);
  result.json = JsonObject({{"experiment", JsonString("hypotheses")},
                          {"world", JsonString(world.path)},
                          {"seed", JsonNumber(static_cast<double>(options.slam.filter.seed))},
                          {"particles", JsonNumber(options.slam.filter.particles)},
                          {"similarity_threshold", JsonNumber(options.slam.predictor.similarity_threshold)},
                          {"mode", JsonString(mode)},
                          {"state", JsonString(ExplorationStateName(summary.state))},
                          {"time_s", JsonNumber(summary.time_s)},
                          {"count", JsonNumber(summary.hypotheses)},
                          {"confirmed", JsonNumber(summary.slam.confirmed)},
                          {"refuted", JsonNumber(summary.slam.refuted)},
                          {"expired", JsonNumber(summary.slam.expired)},
                          {"judged", JsonNumber(agreement.judged)},
                          {"judged_as_truth", JsonNumber(agreement.as_truth)},
                          {"predictions", JsonNumber(summary.slam.predictions_made)},
                          {"ambiguous", JsonNumber(static_cast<double>(summary.slam.outcomes.ambiguous))},
                          {"predicted_area_m2", JsonNumber(predicted_area)},
                          {"summed_hypothesis_area_m2", JsonNumber(summed_area)},
                          {"covered_area_m2", JsonNumber(covered_area)},
                          {"predicted_area_fraction", JsonNumber(fraction)},
                          {"psi_final", JsonArray(psi_final)},
                          {"psi_final_paper_cells", JsonArray(psi_final_paper_cells)},
                          {"psi_truth", JsonArray(psi_truth)},
                          {"psi_search", JsonArray(psi_search)},
                          {"final", SummaryJson(final_summary)},
                          {"final_paper_cells", SummaryJson(paper_cells_summary)},
                          {"truth", SummaryJson(truth_summary)}});
  return result;
}

}  // namespace

int RunHypothesesExperiment(CliArgs& cli) {
  const bool help = cli.Flag("--help");
  const std::vector<WorldChoice> worlds = ChooseWorlds(cli, "office");
  ExplorationOptions options = ExplorationFromCli(cli, 7200.0);
  const std::string mode = cli.Value("--mode").value_or("full");
  const std::optional<std::string> json_path = cli.Value("--json");
  const std::optional<std::string> save_prefix = cli.Value("--save");
  ProgressLine progress(ProgressWanted(cli));
  if (help) {
    std::printf("%s%s%s", kUsage, kGeneratedWorldsUsage, kExplorationFlagsUsage);
    return 0;
  }
  if (mode != "full" && mode != "skip") cli.AddError("--mode is full or skip, got '" + mode + "'");
  if (save_prefix && worlds.size() > 1) cli.AddError("--save takes one world");
  if (!cli.ok() || worlds.empty()) {
    std::fprintf(stderr, "%s%s%s%s", cli.error().c_str(), kUsage, kGeneratedWorldsUsage, kExplorationFlagsUsage);
    return 2;
  }
  try {
    std::vector<HypothesesResult> results;
    for (const WorldChoice& world : worlds) {
      results.push_back(RunOneWorld(world, options, mode, save_prefix, progress));
      if (worlds.size() > 1) std::printf("\n");
    }
    if (worlds.size() == 1) {
      if (json_path) WriteJsonFile(*json_path, results.front().json);
      return 0;
    }
    // Over the population; runs that hit the time limit are counted, and their hypotheses still scored.
    std::vector<double> count, truth_mean, truth_share, final_share;
    int limits = 0;
    for (const HypothesesResult& r : results) {
      limits += r.time_limit;
      count.push_back(r.count);
      truth_mean.push_back(r.truth_mean);
      truth_share.push_back(r.truth_share);
      final_share.push_back(r.final_share);
    }
    std::printf("over %zu worlds; figures as mean +- std [min, max] (n: worlds with a value)\n", results.size());
    std::printf("time limit hit           %d run(s)\n", limits);
    std::printf("hypotheses per world     %s\n", SpreadText(SpreadOf(count), 1.0, "%.1f").c_str());
    std::printf("mean Psi vs truth        %s  (paper, vs final map: 0.51)\n", SpreadText(SpreadOf(truth_mean)).c_str());
    std::printf("share >= 0.4 vs truth    %s %%  (paper, vs final map: 64 %%)\n",
                SpreadText(SpreadOf(truth_share), 100.0, "%.1f").c_str());
    std::printf("share >= 0.4 vs final    %s %%\n", SpreadText(SpreadOf(final_share), 100.0, "%.1f").c_str());
    if (json_path) {
      std::vector<std::string> each;
      for (const HypothesesResult& r : results) each.push_back(r.json);
      WriteJsonFile(*json_path, JsonObject({{"experiment", JsonString("hypotheses")},
                                            {"time_limit_runs", JsonNumber(limits)},
                                            {"hypotheses_per_world", SpreadJson(SpreadOf(count))},
                                            {"mean_psi_truth", SpreadJson(SpreadOf(truth_mean))},
                                            {"share_at_least_0_4_truth", SpreadJson(SpreadOf(truth_share))},
                                            {"share_at_least_0_4_final", SpreadJson(SpreadOf(final_share))},
                                            {"worlds", JsonArray(each)}}));
    }
    return 0;
  } catch (const std::exception& e) {
    progress.Finish();
    std::fprintf(stderr, "pslam experiment hypotheses: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
