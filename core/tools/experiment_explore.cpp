// `pslam experiment explore`: the maze simulation of the paper (Sec. V-A1). The plain RBPF explores
// with full coverage; P-SLAM explores again, skipping frontiers whose surroundings its hypotheses
// already cover. The paper saved 33 % of the time (684 s -> 457 s) with a merged map that
// "predicted the structures inside the unexplored regions reasonably well"; here that is measured
// as Psi (eq. 5) of the merged predicted cells against the true world.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <exception>
#include <string>
#include <vector>

#include "experiment_common.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam experiment explore [--world FILE.yaml] [--start X,Y,THETA] [--runs N] [--json OUT]\n"
    "                                [--save PREFIX] [--skip-fraction F] [--skip-radius M]\n"
    "                                [--plan-on-best-map] [--unbounded] [--pslam-mode skip|full]\n"
    "                                [--quiet] [options]\n"
    "  Explores the world with the plain RBPF and full coverage, then with P-SLAM skipping predicted\n"
    "  regions, and compares the exploration times; --runs repeats both with seeds S, S+1, ...\n"
    "  Default world: core/worlds/maze.yaml. --skip-fraction and --skip-radius tune when a frontier\n"
    "  counts as predicted (0.8, 2 m). P-SLAM plans on the map with its predictions merged in;\n"
    "  --plan-on-best-map plans on the built map alone. The world's boundary is known, as for the\n"
    "  paper's Fig. 7(d): no frontier outside it is explored; --unbounded drops that (Fig. 7(e)).\n"
    "  --pslam-mode full runs P-SLAM with full coverage too, to compare maps with the same explorer\n"
    "  (the irregular world). --save PREFIX writes PREFIX_full, PREFIX_skip and PREFIX_skip_merged\n"
    "  maps of the first run (.pgm/.yaml/.png).\n";

struct ExploreRow {
  std::string name;
  std::uint64_t seed = 0;
  ExplorationSummary summary;
  double map_psi = 0.0;            // built map against the true world
  std::vector<double> psi_truth;   // per accepted hypothesis, against the true world
  double merged_psi = std::numeric_limits<double>::quiet_NaN();
  double merged_area_m2 = 0.0;
  double mapped_or_predicted = 0.0;  // share of the world's free area mapped or predicted at the end
  int judged = 0;                  // hypotheses confirmed or refuted by P-SLAM's judge
  int judged_as_truth = 0;         // of which the verdict matches Psi vs truth >= confirm_psi
};

std::string RowJson(const ExploreRow& row) {
  const ExplorationSummary& s = row.summary;
  return JsonObject({{"name", JsonString(row.name)},
                     {"seed", JsonNumber(static_cast<double>(row.seed))},
                     {"state", JsonString(ExplorationStateName(s.state))},
                     {"time_s", JsonNumber(s.time_s)},
                     {"distance_m", JsonNumber(s.distance_m)},
                     {"collisions", JsonNumber(static_cast<double>(s.collisions))},
                     {"targets", JsonNumber(s.targets)},
                     {"given_up", JsonNumber(s.given_up)},
                     {"hypotheses", JsonNumber(s.hypotheses)},
                     {"confirmed", JsonNumber(s.slam.confirmed)},
                     {"refuted", JsonNumber(s.slam.refuted)},
                     {"expired", JsonNumber(s.slam.expired)},
                     {"new_targets", JsonNumber(s.slam.new_targets)},
                     {"predictions", JsonNumber(s.slam.predictions_made)},
                     {"no_control_point", JsonNumber(static_cast<double>(s.slam.outcomes.no_control_point))},
                     {"too_little_structure", JsonNumber(static_cast<double>(s.slam.outcomes.too_little_structure))},
                     {"below_threshold", JsonNumber(static_cast<double>(s.slam.outcomes.below_threshold))},
                     {"ambiguous", JsonNumber(static_cast<double>(s.slam.outcomes.ambiguous))},
                     {"judged", JsonNumber(row.judged)},
                     {"judged_as_truth", JsonNumber(row.judged_as_truth)},
                     {"mean_position_error_m", JsonNumber(s.mean_position_error_m)},
                     {"max_position_error_m", JsonNumber(s.max_position_error_m)},
                     {"map_psi", JsonNumber(row.map_psi)},
                     {"merged_psi", JsonNumber(row.merged_psi)},
                     {"merged_predicted_area_m2", JsonNumber(row.merged_area_m2)},
                     {"mapped_or_predicted_fraction", JsonNumber(row.mapped_or_predicted)},
                     {"psi_truth", JsonArray(row.psi_truth)}});
}

void PrintHeader() {
  std::printf("%-24s %4s %8s %8s %7s %5s %5s  %-10s %9s %8s %7s\n", "run", "seed", "time_s", "dist_m", "targets",
              "hyp", "coll", "state", "pos_err_m", "map_psi", "psi_hyp");
}

// Mean of the finite values (NaN: a hypothesis with no cell inside the world); 'count' gets how many.
double FiniteMean(const std::vector<double>& values, int* count = nullptr) {
  double sum = 0.0;
  int n = 0;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    sum += v;
    ++n;
  }
  if (count) *count = n;
  return n ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

void PrintRow(const ExploreRow& row) {
  const ExplorationSummary& s = row.summary;
  std::printf("%-24s %4llu %8.1f %8.1f %7d %5d %5zu  %-10s %9.3f %8.3f %7.3f\n", row.name.c_str(),
              static_cast<unsigned long long>(row.seed), s.time_s, s.distance_m, s.targets, s.hypotheses,
              s.collisions, ExplorationStateName(s.state), s.mean_position_error_m, row.map_psi,
              FiniteMean(row.psi_truth));
}

ExploreRow RunOne(const std::string& name, const WorldChoice& world, const OccupancyGrid& truth,
                  const ExplorationOptions& options, ProgressLine& progress, const std::string& save_prefix) {
  ExplorationRun run(world.world, world.start, options);
  ExploreRow row;
  row.name = name;
  row.seed = options.slam.filter.seed;
  row.summary = RunExplorationWithProgress(run, name + " seed " + std::to_string(row.seed), progress);
  row.map_psi = BuiltMapSimilarity(run.slam().filter().best().map, truth);
  for (const auto& cells : AcceptedCellsInWorld(run)) row.psi_truth.push_back(PredictionSimilarity(cells, truth));
  const JudgeAgreement agreement = CountJudgedAsTruth(run, row.psi_truth);
  row.judged = agreement.judged;
  row.judged_as_truth = agreement.as_truth;
  std::vector<HypothesisCell> merged;
  if (options.slam.predict) {
    merged = MergedPredictedCells(run.slam(), [&run](int id) { return AcceptedMapToWorld(run, id); });
    row.merged_psi = PredictionSimilarity(merged, truth);
    row.merged_area_m2 = static_cast<double>(merged.size()) * truth.resolution() * truth.resolution();
  }
  row.mapped_or_predicted = MappedOrPredictedFraction(truth, run.slam().filter().best().map, merged);
  if (!save_prefix.empty()) {
    SaveMap(run.slam().filter().best().map, save_prefix);
    if (options.slam.predict) SaveMap(run.slam().MergedMap(), save_prefix + "_merged");
  }
  return row;
}

}  // namespace

int RunExploreExperiment(CliArgs& cli) {
  const bool help = cli.Flag("--help");
  const std::optional<WorldChoice> world = ChooseWorld(cli, "maze");
  ExplorationOptions options = ExplorationFromCli(cli, 2400.0);
  const int runs = cli.Int("--runs", 1);
  options.explore.skip_covered_fraction = cli.Double("--skip-fraction", options.explore.skip_covered_fraction);
  options.explore.skip_radius = cli.Double("--skip-radius", options.explore.skip_radius);
  options.plan_on_merged_map = !cli.Flag("--plan-on-best-map");
  const bool unbounded = cli.Flag("--unbounded");
  const std::string pslam_mode = cli.Value("--pslam-mode").value_or("skip");
  const std::optional<std::string> json_path = cli.Value("--json");
  const std::optional<std::string> save_prefix = cli.Value("--save");
  ProgressLine progress(ProgressWanted(cli));
  if (help) {
    std::printf("%s%s", kUsage, kExplorationFlagsUsage);
    return 0;
  }
  if (runs < 1) cli.AddError("--runs must be at least 1");
  if (pslam_mode != "skip" && pslam_mode != "full") cli.AddError("--pslam-mode is skip or full, got '" + pslam_mode + "'");
  if (!cli.ok() || !world) {
    std::fprintf(stderr, "%s%s%s", cli.error().c_str(), kUsage, kExplorationFlagsUsage);
    return 2;
  }
  try {
    if (!unbounded) options.explore.area = world->world.Extent();
    const OccupancyGrid truth = world->world.ToGrid();
    const std::uint64_t first_seed = options.slam.filter.seed;
    std::printf("world %s, start (%.2f, %.2f, %.3f), %d particles, similarity threshold %.2f, %d run(s)\n",
                world->path.c_str(), world->start.x, world->start.y, world->start.theta,
                options.slam.filter.particles, options.slam.predictor.similarity_threshold, runs);
    std::vector<ExploreRow> full_rows, skip_rows;
    for (int r = 0; r < runs; ++r) {
      ExplorationOptions seeded = options;
      seeded.slam.filter.seed = seeded.simulator.seed = first_seed + static_cast<std::uint64_t>(r);
      const std::string prefix = save_prefix && r == 0 ? *save_prefix : "";
      ExplorationOptions full = seeded;
      full.slam.predict = false;
      full.explore.mode = ExploreMode::kFullCoverage;
      full_rows.push_back(RunOne("RBPF, full coverage", *world, truth, full, progress, prefix.empty() ? "" : prefix + "_full"));
      ExplorationOptions skip = seeded;
      skip.slam.predict = true;
      skip.explore.mode = pslam_mode == "full" ? ExploreMode::kFullCoverage : ExploreMode::kSkipPredicted;
      skip_rows.push_back(RunOne(pslam_mode == "full" ? "P-SLAM, full coverage" : "P-SLAM, skip predicted", *world, truth,
                                 skip, progress, prefix.empty() ? "" : prefix + "_skip"));
    }

    PrintHeader();
    std::vector<double> time_full, time_skip, merged_psi, hypothesis_psi, map_psi_full, map_psi_skip, covered_full,
        covered_skip;
    bool unfinished = false;
    for (std::size_t r = 0; r < full_rows.size(); ++r) {
      const ExploreRow& full = full_rows[r];
      const ExploreRow& skip = skip_rows[r];
      PrintRow(full);
      PrintRow(skip);
      time_full.push_back(full.summary.time_s);
      time_skip.push_back(skip.summary.time_s);
      merged_psi.push_back(skip.merged_psi);
      map_psi_full.push_back(full.map_psi);
      map_psi_skip.push_back(skip.map_psi);
      covered_full.push_back(full.mapped_or_predicted);
      covered_skip.push_back(skip.mapped_or_predicted);
      hypothesis_psi.insert(hypothesis_psi.end(), skip.psi_truth.begin(), skip.psi_truth.end());
      unfinished = unfinished || full.summary.state != ExplorationState::kExplored ||
                   skip.summary.state != ExplorationState::kExplored;
    }
    const double mean_full = FiniteMean(time_full), mean_skip = FiniteMean(time_skip);
    const double saved = mean_full > 0.0 ? (mean_full - mean_skip) / mean_full : 0.0;
    int scored = 0, good = 0, judged = 0, judged_as_truth = 0;
    for (const ExploreRow& row : skip_rows) {
      judged += row.judged;
      judged_as_truth += row.judged_as_truth;
    }
    const double mean_hypothesis_psi = FiniteMean(hypothesis_psi, &scored);
    for (const double v : hypothesis_psi) good += v >= 0.5;
    std::printf("exploration time         RBPF full %.1f s, P-SLAM %s %.1f s (mean of %d): %.1f %% saved  (paper: 684 s -> 457 s, 33 %%)\n",
                mean_full, pslam_mode.c_str(), mean_skip, runs, 100.0 * saved);
    std::printf("merged predictions       Psi vs true world %.3f (eq. 5 over the predicted cells left unexplored)\n",
                FiniteMean(merged_psi));
    std::printf("mapped or predicted      RBPF %.1f %%, P-SLAM %.1f %% of the true world's free area\n",
                100.0 * FiniteMean(covered_full), 100.0 * FiniteMean(covered_skip));
    std::printf("hypotheses               %zu accepted, Psi vs true world: mean %.3f over %d, %d with Psi >= 0.5\n",
                hypothesis_psi.size(), mean_hypothesis_psi, scored, good);
    std::printf("judge vs true world      %d of %d confirmed/refuted hypotheses agree with Psi vs truth >= %.2f\n",
                judged_as_truth, judged, options.slam.judge.confirm_psi);
    std::printf("built map vs true world  Psi RBPF %.3f, P-SLAM %.3f\n", FiniteMean(map_psi_full), FiniteMean(map_psi_skip));
    if (unfinished) std::printf("note: a run did not finish exploring (see state); its time is a lower bound\n");

    if (json_path) {
      std::vector<std::string> rows;
      for (std::size_t r = 0; r < full_rows.size(); ++r) {
        rows.push_back(RowJson(full_rows[r]));
        rows.push_back(RowJson(skip_rows[r]));
      }
      WriteJsonFile(*json_path,
                    JsonObject({{"experiment", JsonString("explore")},
                                {"world", JsonString(world->path)},
                                {"first_seed", JsonNumber(static_cast<double>(first_seed))},
                                {"runs_per_mode", JsonNumber(runs)},
                                {"particles", JsonNumber(options.slam.filter.particles)},
                                {"similarity_threshold", JsonNumber(options.slam.predictor.similarity_threshold)},
                                {"skip_covered_fraction", JsonNumber(options.explore.skip_covered_fraction)},
                                {"skip_radius_m", JsonNumber(options.explore.skip_radius)},
                                {"plan_on_merged_map", options.plan_on_merged_map ? "true" : "false"},
                                {"area_known", unbounded ? "false" : "true"},
                                {"pslam_mode", JsonString(pslam_mode)},
                                {"time_full_s", JsonNumber(mean_full)},
                                {"time_skip_s", JsonNumber(mean_skip)},
                                {"saved_fraction", JsonNumber(saved)},
                                {"merged_psi", JsonNumber(FiniteMean(merged_psi))},
                                {"hypotheses", JsonNumber(static_cast<double>(hypothesis_psi.size()))},
                                {"mean_hypothesis_psi_truth", JsonNumber(mean_hypothesis_psi)},
                                {"map_psi_full", JsonNumber(FiniteMean(map_psi_full))},
                                {"map_psi_skip", JsonNumber(FiniteMean(map_psi_skip))},
                                {"mapped_or_predicted_full", JsonNumber(FiniteMean(covered_full))},
                                {"mapped_or_predicted_skip", JsonNumber(FiniteMean(covered_skip))},
                                {"runs", JsonArray(rows)}}));
    }
    return 0;
  } catch (const std::exception& e) {
    progress.Finish();
    std::fprintf(stderr, "pslam experiment explore: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
