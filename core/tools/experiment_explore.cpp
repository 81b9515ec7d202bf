// `pslam experiment explore`: the maze simulation of the paper (Sec. V-A1). The plain RBPF explores
// with full coverage; P-SLAM explores again, skipping frontiers whose surroundings its hypotheses
// already cover. The paper saved 33 % of the time (684 s -> 457 s) with a merged map that
// "predicted the structures inside the unexplored regions reasonably well"; here that is measured
// as Psi (eq. 5) of the merged predicted cells against the true world.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "experiment_common.hpp"
#include "pslam/experiment/equal_coverage.hpp"
#include "pslam/experiment/map_alignment.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/experiment/observable_truth.hpp"
#include "pslam/io/map_io.hpp"
#include "pslam/predict/library_map.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam experiment explore [--world FILE.yaml] [--start X,Y,THETA] [--runs N] [--json OUT]\n"
    "                                [--save PREFIX] [--skip-fraction F] [--skip-radius M]\n"
    "                                [--plan-on-best-map] [--unbounded] [--pslam-mode skip|full]\n"
    "                                [--library MAP.yaml]... [--quiet] [options]\n"
    "  Explores the world with the plain RBPF and full coverage, then with P-SLAM skipping predicted\n"
    "  regions, and compares the exploration times; --runs repeats both with seeds S, S+1, ...\n"
    "  Default world: core/worlds/maze.yaml. --skip-fraction and --skip-radius tune when a frontier\n"
    "  counts as predicted (0.8, 2 m). P-SLAM plans on the map with its predictions merged in;\n"
    "  --plan-on-best-map plans on the built map alone. The world's boundary is known, as for the\n"
    "  paper's Fig. 7(d): no frontier outside it is explored; --unbounded drops that (Fig. 7(e)).\n"
    "  --pslam-mode full runs P-SLAM with full coverage too, to compare maps with the same explorer\n"
    "  (the irregular world). --save PREFIX writes PREFIX_full, PREFIX_skip and PREFIX_skip_merged\n"
    "  maps of the first run (.pgm/.yaml/.png).\n"
    "  --library MAP.yaml (repeatable): a map of the site (another floor of the same plan) the\n"
    "  predictor searches for references too; each pair then has a third run, P-SLAM skipping\n"
    "  predicted regions without the library, and both skip runs are compared with full coverage.\n"
    "  Time saved is measured at equal coverage: both runs are timed to the share of the reachable free\n"
    "  area that full coverage mapped, less --coverage-tolerance (0.02); a skip run that never gets\n"
    "  there saves 0. Pairs where a run hit --time-limit, or full coverage ended below 90 % of the\n"
    "  reachable area, are listed but left out of the time figures. Without --time-limit each world\n"
    "  gets 8 simulated seconds per m^2 of its free area, at least 2400 s. Predictions are scored\n"
    "  against the true world, and against what a laser could map of it from the reachable floor\n"
    "  (m_seen): the floor and the faces around it, not the inside of solid blocks or sealed rooms.\n";

struct ExploreRow {
  std::string name;
  std::string world;
  std::uint64_t seed = 0;
  ExplorationSummary summary;
  MapAlignment alignment;          // built map against the true world: psi as it lies, laid_psi laid onto it
  std::vector<double> psi_truth;   // per accepted hypothesis, against the true world
  std::vector<double> psi_observable;  // the same against what a laser could map of it (ObservableTruth)
  std::vector<bool> from_library;  // per accepted hypothesis: its reference is a library map
  double merged_psi = std::numeric_limits<double>::quiet_NaN();
  double merged_psi_observable = std::numeric_limits<double>::quiet_NaN();
  double merged_area_m2 = 0.0;
  double mapped_or_predicted = 0.0;  // share of the reachable free area mapped or predicted at the end
  CoverageTrace coverage;
  int judged = 0;                  // hypotheses confirmed or refuted by P-SLAM's judge
  int judged_as_truth = 0;         // of which the verdict matches Psi vs truth >= confirm_psi
};

std::string RowJson(const ExploreRow& row) {
  const ExplorationSummary& s = row.summary;
  // Coverage over time, to see where a skip run gains or loses against full coverage.
  std::vector<double> coverage_time, coverage_fraction;
  for (const auto& [time, fraction] : row.coverage.samples) {
    coverage_time.push_back(time);
    coverage_fraction.push_back(fraction);
  }
  return JsonObject({{"name", JsonString(row.name)},
                     {"world", JsonString(row.world)},
                     {"seed", JsonNumber(static_cast<double>(row.seed))},
                     {"state", JsonString(ExplorationStateName(s.state))},
                     {"time_s", JsonNumber(s.time_s)},
                     {"distance_m", JsonNumber(s.distance_m)},
                     {"collisions", JsonNumber(static_cast<double>(s.collisions))},
                     {"targets", JsonNumber(s.targets)},
                     {"given_up", JsonNumber(s.given_up)},
                     {"plans", JsonNumber(s.plans)},
                     {"planning_ms_per_plan", JsonNumber(s.plans > 0 ? s.planning_ms / s.plans : 0.0)},
                     {"max_planning_ms", JsonNumber(s.max_planning_ms)},
                     {"expanded_cells_per_plan", JsonNumber(s.plans > 0 ? s.expanded_nodes / s.plans : 0.0)},
                     {"way_ins", JsonNumber(s.way_ins)},
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
                     {"map_psi", JsonNumber(row.alignment.psi)},
                     {"aligned_map_psi", JsonNumber(row.alignment.laid_psi)},
                     {"alignment_shift_m", JsonNumber(row.alignment.centre_shift)},
                     {"alignment_turn_rad", JsonNumber(row.alignment.move.theta)},
                     {"merged_psi", JsonNumber(row.merged_psi)},
                     {"merged_psi_observable", JsonNumber(row.merged_psi_observable)},
                     {"merged_predicted_area_m2", JsonNumber(row.merged_area_m2)},
                     {"mapped_or_predicted_fraction", JsonNumber(row.mapped_or_predicted)},
                     {"coverage_time_s", JsonArray(coverage_time)},
                     {"coverage_fraction", JsonArray(coverage_fraction)},
                     {"psi_truth", JsonArray(row.psi_truth)},
                     {"psi_observable", JsonArray(row.psi_observable)},
                     {"library_hypotheses", JsonNumber(static_cast<double>(
                                                std::count(row.from_library.begin(), row.from_library.end(), true)))}});
}

void PrintHeader() {
  std::printf("%-24s %4s %8s %8s %7s %5s %5s  %-10s %9s %8s %7s %7s %7s %8s\n", "run", "seed", "time_s", "dist_m", "targets",
              "hyp", "coll", "state", "pos_err_m", "map_psi", "aligned", "psi_hyp", "plan_ms", "max_ms");
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
  std::printf("%-24s %4llu %8.1f %8.1f %7d %5d %5zu  %-10s %9.3f %8.3f %7.3f %7.3f %7.1f %8.1f\n", row.name.c_str(),
              static_cast<unsigned long long>(row.seed), s.time_s, s.distance_m, s.targets, s.hypotheses,
              s.collisions, ExplorationStateName(s.state), s.mean_position_error_m, row.alignment.psi, row.alignment.laid_psi,
              FiniteMean(row.psi_truth), s.plans > 0 ? s.planning_ms / s.plans : 0.0, s.max_planning_ms);
}

constexpr double kCoverageSamplePeriodS = 10.0;

ExploreRow RunOne(const std::string& name, const WorldChoice& world, const OccupancyGrid& truth,
                  const OccupancyGrid& observable, const OccupancyGrid& reachable, const ExplorationOptions& options,
                  ProgressLine& progress, const std::string& save_prefix) {
  ExplorationRun run(world.world, world.start, options);
  ExploreRow row;
  row.name = name;
  row.world = world.path;
  row.seed = options.slam.filter.seed;
  const std::string label = name + " seed " + std::to_string(row.seed);
  row.coverage = RunRecordingCoverage(run, reachable, kCoverageSamplePeriodS, [&] {
    char line[160];
    std::snprintf(line, sizeof line, "%s: %.0f / %.0f simulated s, %zu hypotheses", label.c_str(), run.time(),
                  run.options().time_limit_s, run.accepted_hypotheses().size());
    progress.Show(line);
  });
  progress.Finish();
  row.summary = run.Summary();
  const OccupancyGrid& built = run.slam().filter().best().map;
  row.alignment = AlignMap(built, truth);
  for (const auto& cells : AcceptedCellsInWorld(run)) {
    row.psi_truth.push_back(PredictionSimilarity(cells, truth));
    row.psi_observable.push_back(PredictionSimilarity(cells, observable));
  }
  for (const Hypothesis& h : run.accepted_hypotheses()) row.from_library.push_back(!h.reference_map.empty());
  const JudgeAgreement agreement = CountJudgedAsTruth(run, row.psi_truth);
  row.judged = agreement.judged;
  row.judged_as_truth = agreement.as_truth;
  std::vector<HypothesisCell> merged;
  if (options.slam.predict) {
    merged = MergedPredictedCells(run.slam(), [&run](int id) { return AcceptedMapToWorld(run, id); });
    row.merged_psi = PredictionSimilarity(merged, truth);
    row.merged_psi_observable = PredictionSimilarity(merged, observable);
    row.merged_area_m2 = static_cast<double>(merged.size()) * truth.resolution() * truth.resolution();
  }
  row.mapped_or_predicted = row.coverage.Final();
  if (!save_prefix.empty()) {
    SaveMap(run.slam().filter().best().map, save_prefix);
    if (options.slam.predict) SaveMap(run.slam().MergedMap(), save_prefix + "_merged");
    SaveMappingTrajectory(MappingTrajectoryPath(save_prefix), run.MappedTrajectory());
  }
  return row;
}

// One full-coverage run and one P-SLAM run of the same world and seed, compared at equal coverage.
struct ExplorePair {
  ExploreRow full, skip;
  EqualCoverageSaving saving;
  // With --library: 'skip' used the library, and this run did not.
  std::optional<ExploreRow> skip_alone;
  EqualCoverageSaving saving_alone;
  double time_limit_s = 0.0;
  bool time_limit = false;  // either run hit the time limit: listed, never averaged as finished
  // Full coverage ended short of kCompleteCoverage (it gave its targets up): nothing to time against.
  bool full_incomplete = false;
};

constexpr double kCompleteCoverage = 0.9;

void PrintPairHeader() {
  std::printf("%-28s %4s %8s %8s %9s %9s %8s %8s %8s %8s  %s\n", "world", "seed", "full_s", "skip_s", "cov_full",
              "cov_skip", "equal_at", "saved", "merged", "m_seen", "flags");
}

void PrintPair(const ExplorePair& p) {
  std::string flags;
  if (p.full.summary.state == ExplorationState::kTimeLimit) flags += "full-hit-time-limit ";
  if (p.skip.summary.state == ExplorationState::kTimeLimit) flags += "skip-hit-time-limit ";
  if (p.full.summary.state == ExplorationState::kStuck) flags += "full-stuck ";
  if (p.skip.summary.state == ExplorationState::kStuck) flags += "skip-stuck ";
  if (p.full_incomplete) flags += "full-incomplete ";
  if (!p.saving.skip_reached) flags += "skip-below-equal-coverage(saved 0) ";
  char skip_time[32];
  if (p.saving.skip_reached) std::snprintf(skip_time, sizeof skip_time, "%.0f", p.saving.skip_time_s);
  else std::snprintf(skip_time, sizeof skip_time, "never");
  std::printf("%-28s %4llu %8.1f %8.1f %8.1f%% %8.1f%% %8.1f%% %5.0f/%-5s %7.1f%% %8.3f %8.3f  %s\n",
              p.full.world.c_str(), static_cast<unsigned long long>(p.full.seed), p.full.summary.time_s,
              p.skip.summary.time_s,
              100.0 * p.full.mapped_or_predicted, 100.0 * p.skip.mapped_or_predicted, 100.0 * p.saving.target,
              p.saving.full_time_s, skip_time, 100.0 * p.saving.saved_fraction, p.skip.merged_psi,
              p.skip.merged_psi_observable, flags.empty() ? "-" : flags.c_str());
}

// The library's hypotheses of a skip run: how many, and their mean Psi against the true world.
void PrintLibraryLine(const ExploreRow& row) {
  std::vector<double> psi_library, psi_built;
  for (std::size_t i = 0; i < row.psi_truth.size() && i < row.from_library.size(); ++i) {
    (row.from_library[i] ? psi_library : psi_built).push_back(row.psi_truth[i]);
  }
  std::printf("  %s: %zu hypotheses from the library (Psi vs truth %.3f), %zu from the built map (%.3f)\n",
              row.name.c_str(), psi_library.size(), FiniteMean(psi_library), psi_built.size(), FiniteMean(psi_built));
}

MapLibrary LoadLibrary(const std::vector<std::string>& paths, const PredictorOptions& options) {
  MapLibrary library;
  for (const std::string& path : paths) library.push_back(MakeLibraryMap(path, LoadMap(path), options));
  return library;
}

}  // namespace

int RunExploreExperiment(CliArgs& cli) {
  const bool help = cli.Flag("--help");
  const std::vector<WorldChoice> worlds = ChooseWorlds(cli, "maze");
  const bool time_limit_given = cli.Value("--time-limit").has_value();
  ExplorationOptions options = ExplorationFromCli(cli, kMinExplorationTimeS);
  const int runs = cli.Int("--runs", 1);
  options.explore.skip_covered_fraction = cli.Double("--skip-fraction", options.explore.skip_covered_fraction);
  options.explore.skip_radius = cli.Double("--skip-radius", options.explore.skip_radius);
  options.plan_on_merged_map = !cli.Flag("--plan-on-best-map");
  const bool unbounded = cli.Flag("--unbounded");
  const std::string pslam_mode = cli.Value("--pslam-mode").value_or("skip");
  const double tolerance = cli.Double("--coverage-tolerance", 0.02);
  const std::optional<std::string> json_path = cli.Value("--json");
  const std::optional<std::string> save_prefix = cli.Value("--save");
  const std::vector<std::string> library_paths = cli.Values("--library");
  ProgressLine progress(ProgressWanted(cli));
  if (help) {
    std::printf("%s%s%s", kUsage, kGeneratedWorldsUsage, kExplorationFlagsUsage);
    return 0;
  }
  if (runs < 1) cli.AddError("--runs must be at least 1");
  if (!(tolerance >= 0.0 && tolerance < 1.0)) cli.AddError("--coverage-tolerance must lie in [0, 1)");
  if (pslam_mode != "skip" && pslam_mode != "full") cli.AddError("--pslam-mode is skip or full, got '" + pslam_mode + "'");
  if (!cli.ok() || worlds.empty()) {
    std::fprintf(stderr, "%s%s%s%s", cli.error().c_str(), kUsage, kGeneratedWorldsUsage, kExplorationFlagsUsage);
    return 2;
  }
  try {
    const MapLibrary library = LoadLibrary(library_paths, options.slam.predictor);
    if (library.size() > static_cast<std::size_t>(options.slam.predictor.max_library_maps)) {
      std::fprintf(stderr, "pslam experiment explore: at most %d library maps are searched\n",
                   options.slam.predictor.max_library_maps);
      return 2;
    }
    const std::uint64_t first_seed = options.slam.filter.seed;
    const std::string limit_text =
        time_limit_given ? std::to_string(static_cast<long>(options.time_limit_s)) + " s"
                         : std::to_string(static_cast<long>(kExplorationSecondsPerFreeM2)) + " s per m^2 of free area";
    std::printf("%zu world(s), %d particles, similarity threshold %.2f, %d run(s) each, time limit %s\n", worlds.size(),
                options.slam.filter.particles, options.slam.predictor.similarity_threshold, runs, limit_text.c_str());
    std::vector<ExplorePair> pairs;
    for (const WorldChoice& world : worlds) {
      ExplorationOptions world_options = options;
      if (!unbounded) world_options.explore.area = world.world.Extent();
      if (!time_limit_given) world_options.time_limit_s = ExplorationTimeBudget(world.world);
      const OccupancyGrid truth = world.world.ToGrid();
      const OccupancyGrid reachable = ReachableFreeCells(world.world, world.start.translation());
      const OccupancyGrid observable = ObservableTruth(world.world, reachable);
      std::printf("world %s, start (%.2f, %.2f, %.3f), time limit %.0f s\n", world.path.c_str(), world.start.x,
                  world.start.y, world.start.theta, world_options.time_limit_s);
      for (int r = 0; r < runs; ++r) {
        ExplorationOptions seeded = world_options;
        seeded.slam.filter.seed = seeded.simulator.seed = first_seed + static_cast<std::uint64_t>(r);
        const std::string prefix = save_prefix && r == 0 && worlds.size() == 1 ? *save_prefix : "";
        ExplorationOptions full = seeded;
        full.slam.predict = false;
        full.explore.mode = ExploreMode::kFullCoverage;
        ExplorePair pair;
        pair.full = RunOne("RBPF, full coverage", world, truth, observable, reachable, full, progress,
                           prefix.empty() ? "" : prefix + "_full");
        ExplorationOptions skip = seeded;
        skip.slam.predict = true;
        skip.explore.mode = pslam_mode == "full" ? ExploreMode::kFullCoverage : ExploreMode::kSkipPredicted;
        const std::string skip_name = pslam_mode == "full" ? "P-SLAM, full coverage" : "P-SLAM, skip predicted";
        if (!library.empty()) {
          pair.skip_alone = RunOne(skip_name, world, truth, observable, reachable, skip, progress,
                                   prefix.empty() ? "" : prefix + "_skip_alone");
          pair.saving_alone = CompareAtEqualCoverage(pair.full.coverage, pair.skip_alone->coverage, tolerance);
          skip.slam.library = library;
        }
        pair.skip = RunOne(library.empty() ? skip_name : skip_name + ", library", world, truth, observable, reachable,
                           skip, progress, prefix.empty() ? "" : prefix + "_skip");
        pair.saving = CompareAtEqualCoverage(pair.full.coverage, pair.skip.coverage, tolerance);
        pair.time_limit_s = world_options.time_limit_s;
        pair.time_limit = pair.full.summary.state == ExplorationState::kTimeLimit ||
                          pair.skip.summary.state == ExplorationState::kTimeLimit;
        pair.full_incomplete = pair.full.mapped_or_predicted < kCompleteCoverage;
        PrintHeader();
        PrintRow(pair.full);
        if (pair.skip_alone) PrintRow(*pair.skip_alone);
        PrintRow(pair.skip);
        if (!library.empty()) PrintLibraryLine(pair.skip);
        std::fflush(stdout);  // a population run takes hours: each pair shows as soon as it is done
        pairs.push_back(std::move(pair));
      }
    }

    std::printf("\nper pair: times to the end; coverage = mapped or predicted share of the reachable free area;\n"
                "equal_at = full's final coverage - %.2f, reached by full / skip at the times given\n", tolerance);
    PrintPairHeader();
    for (const ExplorePair& p : pairs) PrintPair(p);
    if (!library.empty()) {
      std::printf("\nthe same pairs, P-SLAM without the library:\n");
      PrintPairHeader();
      for (const ExplorePair& p : pairs) {
        ExplorePair alone = p;
        alone.skip = *p.skip_alone;
        alone.saving = p.saving_alone;
        PrintPair(alone);
      }
    }

    // Population figures. Time figures only over pairs where neither run hit the time limit.
    std::vector<double> saved, equal_full, equal_skip, end_full, end_skip, merged_psi, merged_psi_observable,
        hypothesis_psi, hypothesis_psi_observable, per_run_psi,
        per_run_good, covered_full, covered_skip, hypotheses, map_psi_full, map_psi_skip, aligned_full, aligned_skip;
    int incomplete_pairs = 0, time_limit_pairs = 0, full_limits = 0, skip_limits = 0, stopped_early = 0, judged = 0, judged_as_truth = 0;
    for (const ExplorePair& p : pairs) {
      full_limits += p.full.summary.state == ExplorationState::kTimeLimit;
      skip_limits += p.skip.summary.state == ExplorationState::kTimeLimit;
      merged_psi.push_back(p.skip.merged_psi);
      merged_psi_observable.push_back(p.skip.merged_psi_observable);
      covered_full.push_back(p.full.mapped_or_predicted);
      covered_skip.push_back(p.skip.mapped_or_predicted);
      hypotheses.push_back(p.skip.summary.hypotheses);
      map_psi_full.push_back(p.full.alignment.psi);
      map_psi_skip.push_back(p.skip.alignment.psi);
      aligned_full.push_back(p.full.alignment.laid_psi);
      aligned_skip.push_back(p.skip.alignment.laid_psi);
      hypothesis_psi.insert(hypothesis_psi.end(), p.skip.psi_truth.begin(), p.skip.psi_truth.end());
      hypothesis_psi_observable.insert(hypothesis_psi_observable.end(), p.skip.psi_observable.begin(),
                                       p.skip.psi_observable.end());
      int scored = 0;
      per_run_psi.push_back(FiniteMean(p.skip.psi_truth, &scored));
      if (scored > 0) {
        per_run_good.push_back(static_cast<double>(std::count_if(p.skip.psi_truth.begin(), p.skip.psi_truth.end(),
                                                                 [](double v) { return v >= 0.4; })) / scored);
      }
      judged += p.skip.judged;
      judged_as_truth += p.skip.judged_as_truth;
      if (p.time_limit || p.full_incomplete) {
        time_limit_pairs += p.time_limit;
        incomplete_pairs += p.full_incomplete && !p.time_limit;
        continue;
      }
      stopped_early += !p.saving.skip_reached;
      saved.push_back(p.saving.saved_fraction);
      equal_full.push_back(p.saving.full_time_s);
      if (p.saving.skip_reached) equal_skip.push_back(p.saving.skip_time_s);
      end_full.push_back(p.full.summary.time_s);
      end_skip.push_back(p.skip.summary.time_s);
    }
    int scored = 0, good = 0;
    const double mean_hypothesis_psi = FiniteMean(hypothesis_psi, &scored);
    for (const double v : hypothesis_psi) good += v >= 0.4;
    const Spread saved_spread = SpreadOf(saved);
    std::printf("\nover %zu pair(s); figures as mean +- std [min, max] (n)\n", pairs.size());
    std::printf("time limit hit           %d pair(s) (full %d, skip %d): listed above, left out of the time figures\n",
                time_limit_pairs, full_limits, skip_limits);
    std::printf("full coverage incomplete %d pair(s) ended below %.0f %% of the reachable area: left out too\n",
                incomplete_pairs, 100.0 * kCompleteCoverage);
    std::printf("saved at equal coverage  %s %%  (%d skip run(s) never reached it: 0 saved)  (paper: 33 %%)\n",
                SpreadText(saved_spread, 100.0, "%.1f").c_str(), stopped_early);
    std::printf("time to equal coverage   full %s s, skip %s s\n", SpreadText(SpreadOf(equal_full), 1.0, "%.0f").c_str(),
                SpreadText(SpreadOf(equal_skip), 1.0, "%.0f").c_str());
    std::printf("time to the end          full %s s, skip %s s\n", SpreadText(SpreadOf(end_full), 1.0, "%.0f").c_str(),
                SpreadText(SpreadOf(end_skip), 1.0, "%.0f").c_str());
    const auto at_least = [](const std::vector<double>& values, double bound) {
      return static_cast<int>(std::count_if(values.begin(), values.end(), [bound](double v) { return v >= bound; }));
    };
    std::printf("merged Psi vs truth      %s  (runs >= 0.7: %d)\n", SpreadText(SpreadOf(merged_psi)).c_str(),
                at_least(merged_psi, 0.7));
    std::printf("  vs what can be seen    %s  (runs >= 0.7: %d; the truth but inside solids and sealed rooms)\n",
                SpreadText(SpreadOf(merged_psi_observable)).c_str(), at_least(merged_psi_observable, 0.7));
    std::printf("mapped or predicted      full %s %%, skip %s %% of the reachable free area\n",
                SpreadText(SpreadOf(covered_full), 100.0, "%.1f").c_str(),
                SpreadText(SpreadOf(covered_skip), 100.0, "%.1f").c_str());
    std::printf("hypotheses per run       %s\n", SpreadText(SpreadOf(hypotheses), 1.0, "%.1f").c_str());
    std::printf("hypothesis Psi vs truth  all %zu: mean %.3f over %d scored, %d (%.0f %%) >= 0.4; per run mean %s, "
                "share >= 0.4 %s\n",
                hypothesis_psi.size(), mean_hypothesis_psi, scored, good, scored ? 100.0 * good / scored : 0.0,
                SpreadText(SpreadOf(per_run_psi)).c_str(), SpreadText(SpreadOf(per_run_good)).c_str());
    int scored_observable = 0;
    const double mean_observable = FiniteMean(hypothesis_psi_observable, &scored_observable);
    std::printf("  vs what can be seen    mean %.3f over %d scored, %d >= 0.4\n", mean_observable, scored_observable,
                at_least(hypothesis_psi_observable, 0.4));
    std::printf("judge vs true world      %d of %d confirmed/refuted hypotheses agree with Psi vs truth >= %.2f\n",
                judged_as_truth, judged, options.slam.judge.confirm_psi);
    std::printf("built map vs true world  Psi RBPF %s, P-SLAM %s\n", SpreadText(SpreadOf(map_psi_full)).c_str(),
                SpreadText(SpreadOf(map_psi_skip)).c_str());
    std::printf("  laid onto it first     Psi RBPF %s, P-SLAM %s\n", SpreadText(SpreadOf(aligned_full)).c_str(),
                SpreadText(SpreadOf(aligned_skip)).c_str());

    if (json_path) {
      std::vector<std::string> rows;
      for (const ExplorePair& p : pairs) {
        rows.push_back(JsonObject({{"full", RowJson(p.full)},
                                   {"skip", RowJson(p.skip)},
                                   {"equal_coverage", JsonNumber(p.saving.target)},
                                   {"full_time_to_equal_s", JsonNumber(p.saving.full_time_s)},
                                   {"skip_time_to_equal_s", JsonNumber(p.saving.skip_time_s)},
                                   {"skip_reached_equal_coverage", p.saving.skip_reached ? "true" : "false"},
                                   {"saved_fraction", JsonNumber(p.saving.saved_fraction)},
                                   {"time_limit_s", JsonNumber(p.time_limit_s)},
                                   {"time_limit_hit", p.time_limit ? "true" : "false"},
                                   {"full_incomplete", p.full_incomplete ? "true" : "false"},
                                   {"skip_without_library", p.skip_alone ? RowJson(*p.skip_alone) : "null"},
                                   {"saved_fraction_without_library",
                                    p.skip_alone ? JsonNumber(p.saving_alone.saved_fraction) : "null"}}));
      }
      std::vector<std::string> world_names;
      for (const WorldChoice& w : worlds) world_names.push_back(JsonString(w.path));
      WriteJsonFile(*json_path,
                    JsonObject({{"experiment", JsonString("explore")},
                                {"worlds", JsonArray(world_names)},
                                {"first_seed", JsonNumber(static_cast<double>(first_seed))},
                                {"runs_per_world", JsonNumber(runs)},
                                {"particles", JsonNumber(options.slam.filter.particles)},
                                {"similarity_threshold", JsonNumber(options.slam.predictor.similarity_threshold)},
                                {"skip_covered_fraction", JsonNumber(options.explore.skip_covered_fraction)},
                                {"skip_radius_m", JsonNumber(options.explore.skip_radius)},
                                {"plan_on_merged_map", options.plan_on_merged_map ? "true" : "false"},
                                {"area_known", unbounded ? "false" : "true"},
                                {"pslam_mode", JsonString(pslam_mode)},
                                {"library", JsonArray([&] {
                                   std::vector<std::string> names;
                                   for (const std::string& path : library_paths) names.push_back(JsonString(path));
                                   return names;
                                 }())},
                                {"time_limit_s", time_limit_given ? JsonNumber(options.time_limit_s) : "null"},
                                {"coverage_tolerance", JsonNumber(tolerance)},
                                {"time_limit_pairs", JsonNumber(time_limit_pairs)},
                                {"full_incomplete_pairs", JsonNumber(incomplete_pairs)},
                                {"skip_below_equal_coverage", JsonNumber(stopped_early)},
                                {"saved_at_equal_coverage", SpreadJson(saved_spread)},
                                {"time_to_equal_full_s", SpreadJson(SpreadOf(equal_full))},
                                {"time_to_equal_skip_s", SpreadJson(SpreadOf(equal_skip))},
                                {"merged_psi", SpreadJson(SpreadOf(merged_psi))},
                                {"merged_psi_observable", SpreadJson(SpreadOf(merged_psi_observable))},
                                {"mapped_or_predicted_full", SpreadJson(SpreadOf(covered_full))},
                                {"mapped_or_predicted_skip", SpreadJson(SpreadOf(covered_skip))},
                                {"hypotheses", JsonNumber(static_cast<double>(hypothesis_psi.size()))},
                                {"mean_hypothesis_psi_truth", JsonNumber(mean_hypothesis_psi)},
                                {"mean_hypothesis_psi_observable", JsonNumber(mean_observable)},
                                {"pairs", JsonArray(rows)}}));
    }
    return 0;
  } catch (const std::exception& e) {
    progress.Finish();
    std::fprintf(stderr, "pslam experiment explore: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
