// `pslam experiment latency`: how long one structure prediction takes as the map grows. The paper
// runs the predictor in its own thread on a 2 GHz Pentium-M and reports real-time operation
// (Sec. V-B); the target here is a median of at most 50 ms on a map the size of the Intel lab.
// Growing maps are crops of a world (default: the office, true cells) or of a saved map, widening
// from the start pose's end along the longer axis, as if the robot had explored that far.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

#include "experiment_common.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/experiment/prediction_latency.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam experiment latency [--world FILE.yaml | --map FILE.yaml] [--steps N] [--targets N]\n"
    "                                [--similarity-threshold PSI] [--search-radius M]\n"
    "                                [--max-reference-corners N] [--json OUT] [--quiet]\n"
    "  Times predictions at up to --targets (20) frontier targets on each of --steps (6) crops of the\n"
    "  map, growing along its longer axis to the whole map (a world: to 6/7 of it, since a fully known\n"
    "  world has no frontier). Default: core/worlds/office.yaml. The JSON's\n"
    "  median_ms and p95_ms are CPU time (the machine's load does not inflate them); wall time is\n"
    "  printed and kept beside it.\n";

}  // namespace

int RunLatencyExperiment(CliArgs& cli) {
  const bool help = cli.Flag("--help");
  const std::optional<std::string> map_path = cli.Value("--map");
  std::optional<WorldChoice> world;
  if (!map_path && !help) world = ChooseWorld(cli, "office");
  const int steps = cli.Int("--steps", 6);
  const int targets_per_map = cli.Int("--targets", 20);
  PredictorOptions predictor;
  predictor.similarity_threshold = cli.Double("--similarity-threshold", 0.6);
  predictor.search_radius_m = cli.Double("--search-radius", predictor.search_radius_m);
  predictor.max_reference_corners = cli.Int("--max-reference-corners", predictor.max_reference_corners);
  const std::optional<std::string> json_path = cli.Value("--json");
  ProgressLine progress(ProgressWanted(cli));
  if (help) {
    std::printf("%s", kUsage);
    return 0;
  }
  if (steps < 1 || targets_per_map < 1) cli.AddError("--steps and --targets must be positive");
  if (const auto problem = ValidatePredictorOptions(predictor)) cli.AddError(*problem);
  if (!cli.ok() || (!map_path && !world)) {
    std::fprintf(stderr, "%s%s", cli.error().c_str(), kUsage);
    return 2;
  }
  try {
    const OccupancyGrid full = map_path ? LoadMap(*map_path) : world->world.ToGrid();
    const std::string source = map_path ? *map_path : world->path;
    const CellBox bounds = full.KnownBounds();
    const bool along_x = bounds.width() >= bounds.height();
    std::printf("map %s (%.1f x %.1f m), %d targets per crop, similarity threshold %.2f, search radius %.0f m, "
                "at most %d reference corners\n",
                source.c_str(), bounds.width() * full.resolution(), bounds.height() * full.resolution(), targets_per_map,
                predictor.similarity_threshold, predictor.search_radius_m, predictor.max_reference_corners);
    std::printf("%-42s | %-28s | %-19s | %-19s | %s\n", "", "CPU ms, all predictions", "CPU ms, searched",
                "wall ms, all", "features");
    std::printf("%9s %10s %6s %8s %5s | %8s %8s %8s | %8s %8s | %8s %8s | %s\n", "extent_m", "known_m2", "preds",
                "searched", "hyp", "median", "p95", "max", "median", "p95", "median", "p95", "share");
    std::vector<std::string> rows;
    for (int step = 1; step <= steps; ++step) {
      // Crops grow from the low end of the longer axis: the office's start is at its west end.
      CellBox box = bounds;
      const int length = along_x ? bounds.width() : bounds.height();
      // A world is known everywhere and has no frontier to predict at its full extent, so its crops
      // stop short of it; a built map's last crop is the whole map.
      const int extent = std::max(1, length * step / (map_path ? steps : steps + 1));
      (along_x ? box.max.x() : box.max.y()) = (along_x ? box.min.x() : box.min.y()) + extent - 1;
      const OccupancyGrid crop = CropMap(full, box);
      const std::vector<Eigen::Vector2i> targets = FrontierTargets(crop, targets_per_map);
      char line[120];
      std::snprintf(line, sizeof line, "crop %d of %d: %zu predictions", step, steps, targets.size());
      progress.Show(line, true);
      const LatencyStats stats = MeasurePredictionLatency(crop, targets, predictor);
      progress.Finish();
      const double extent_m = extent * full.resolution();
      const double known = KnownArea(crop);
      std::printf("%9.1f %10.1f %6d %8d %5d | %8.1f %8.1f %8.1f | %8.1f %8.1f | %8.1f %8.1f | %5.0f %%\n", extent_m,
                  known, stats.predictions, stats.searched, stats.hypotheses, stats.cpu_median_ms, stats.cpu_p95_ms,
                  stats.cpu_max_ms, stats.searched_cpu_median_ms, stats.searched_cpu_p95_ms, stats.median_ms,
                  stats.p95_ms, 100.0 * stats.feature_share);
      rows.push_back(JsonObject({{"extent_m", JsonNumber(extent_m)},
                                 {"known_area_m2", JsonNumber(known)},
                                 {"predictions", JsonNumber(stats.predictions)},
                                 {"searched", JsonNumber(stats.searched)},
                                 {"hypotheses", JsonNumber(stats.hypotheses)},
                                 {"median_ms", JsonNumber(stats.cpu_median_ms)},
                                 {"p95_ms", JsonNumber(stats.cpu_p95_ms)},
                                 {"max_ms", JsonNumber(stats.cpu_max_ms)},
                                 {"searched_median_ms", JsonNumber(stats.searched_cpu_median_ms)},
                                 {"searched_p95_ms", JsonNumber(stats.searched_cpu_p95_ms)},
                                 {"feature_share", JsonNumber(stats.feature_share)},
                                 {"wall_median_ms", JsonNumber(stats.median_ms)},
                                 {"wall_p95_ms", JsonNumber(stats.p95_ms)},
                                 {"cpu_ms", JsonArray(stats.cpu_ms)},
                                 {"wall_ms", JsonArray(stats.ms)},
                                 {"best_psi", JsonArray(stats.best_psi)}}));
    }
    if (json_path) {
      WriteJsonFile(*json_path, JsonObject({{"experiment", JsonString("latency")},
                                            {"map", JsonString(source)},
                                            {"targets_per_crop", JsonNumber(targets_per_map)},
                                            {"sizes", JsonArray(rows)}}));
    }
    return 0;
  } catch (const std::exception& e) {
    progress.Finish();
    std::fprintf(stderr, "pslam experiment latency: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
