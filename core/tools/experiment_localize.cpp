// `pslam experiment localize`: Monte Carlo localization of a simulated robot on its world's map,
// from a known start (tracking error) and from none (distance to converge), with the CPU time per
// scan next to the mapping filter's on the same scans.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "experiment_common.hpp"
#include "pslam/experiment/localization_tour.hpp"
#include "pslam/experiment/map_alignment.hpp"
#include "pslam/experiment/mapping_trajectory.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam experiment localize [--world FILE.yaml] [--start X,Y,THETA] [--runs N] [--seed S]\n"
    "                                 [--distance M] [--kidnap-after M --kidnap-pose X,Y,THETA]\n"
    "                                 [--map MAP.yaml] [--mapping] [--no-look-around] [--trace OUT.txt]\n"
    "                                 [--json OUT] [--set NAME=VALUE ...]\n"
    "  Drives the simulated robot along planned paths to random goals (default world:\n"
    "  core/worlds/office.yaml) and localizes it on the world's map (--map: on MAP.yaml instead, in\n"
    "  the world's frame, e.g. the map an earlier exploration built: 'pslam experiment hypotheses\n"
    "  --save PREFIX'), once from the start pose given\n"
    "  with 0.2 m / 0.1 rad of spread (tracking) and once with no pose (global localization), for\n"
    "  seeds S, S+1, ... --kidnap-after carries the robot to --kidnap-pose after M metres in the\n"
    "  tracking run. Whenever the localizer starts searching for its place (a global start, a\n"
    "  kidnapping), the robot first turns once in place; --no-look-around drives on instead.\n"
    "  --mapping also runs the mapping filter over the tracking run's scans for its\n"
    "  CPU time. --trace writes 'distance truth_x truth_y truth_theta x y theta localized particles'\n"
    "  per scan of the last global run. With --map the figures are given twice: against the true\n"
    "  pose, and against the true pose carried into the map's own frame (the map laid onto the world\n"
    "  first), which leaves out how far the map itself sits off. When MAP_trajectory.txt lies beside\n"
    "  MAP.yaml (written with it by --save), a third time: against where the map itself has each\n"
    "  place (the mapping run's own pose at the nearest place it passed, within 1 m), which leaves\n"
    "  out the map's bends as well. --set tunes a localization option:\n";

constexpr double kConverged = 0.2;  // m: global localization has converged below this error

void WriteTrace(const std::string& path, const std::vector<LocalizationSample>& samples) {
  std::ofstream out(path);
  for (const LocalizationSample& s : samples) {
    out << s.distance << ' ' << s.truth.x << ' ' << s.truth.y << ' ' << s.truth.theta << ' ' << s.estimate.x << ' '
        << s.estimate.y << ' ' << s.estimate.theta << ' ' << s.localized << ' ' << s.particles << '\n';
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

// The samples with the truth carried into a map's frame: 'map_to_world' lays the map onto the world.
std::vector<LocalizationSample> InMapFrame(std::vector<LocalizationSample> samples, const Pose2D& map_to_world) {
  const Pose2D world_to_map = map_to_world.inverse();
  for (LocalizationSample& s : samples) s.truth = world_to_map * s.truth;
  return samples;
}

// The samples with the truth carried to where the map has that place; those more than 1 m from
// any place the mapping run passed are left out.
std::vector<LocalizationSample> InMapLocally(const std::vector<LocalizationSample>& samples, const MapLocalFrame& frame) {
  std::vector<LocalizationSample> out;
  for (LocalizationSample s : samples) {
    const std::optional<Pose2D> local = frame.ToMap(s.truth);
    if (!local) continue;
    s.truth = *local;
    out.push_back(s);
  }
  return out;
}

// What one tracking run and one global run show, measured against the truth the samples carry.
struct RunFigures {
  TrackingError tracking;
  std::optional<double> converged_after;  // m driven by the global run
  int localized = 0;                      // scans the global run reported localized
  int wrongly = 0;                        // ... with the estimate kConverged or more off
  double wrongly_share = 0.0;             // wrongly over all the global run's scans
};

RunFigures Measure(const std::vector<LocalizationSample>& tracking, const std::vector<LocalizationSample>& global) {
  RunFigures f;
  f.tracking = MeasureTracking(tracking, 2.0);
  f.converged_after = ConvergenceDistance(global, kConverged);
  for (const LocalizationSample& s : global) {
    if (!s.localized) continue;
    ++f.localized;
    if ((s.estimate.translation() - s.truth.translation()).norm() >= kConverged) ++f.wrongly;
  }
  // Honesty: the share of scans that reported "localized" while the estimate was wrong.
  f.wrongly_share = global.empty() ? 0.0 : static_cast<double>(f.wrongly) / static_cast<double>(global.size());
  return f;
}

std::string ConvergenceText(const RunFigures& f) {
  return f.converged_after ? "converged after " + std::to_string(*f.converged_after) + " m" : "did not converge";
}

// The figures of every run, against one truth.
struct FigureSeries {
  std::vector<double> position, heading, converge, wrongly_share;
  int never = 0;

  void Add(const RunFigures& f) {
    position.push_back(f.tracking.mean_position);
    heading.push_back(f.tracking.mean_heading);
    wrongly_share.push_back(f.wrongly_share);
    if (f.converged_after) converge.push_back(*f.converged_after);
    else ++never;
  }
  // The JSON members, each name prefixed.
  std::vector<std::pair<std::string, std::string>> Json(const std::string& prefix) const {
    return {{prefix + "tracking_position_error_m", JsonArray(position)},
            {prefix + "tracking_heading_error_rad", JsonArray(heading)},
            {prefix + "global_converged_after_m", JsonArray(converge)},
            {prefix + "global_not_converged", JsonNumber(never)},
            {prefix + "global_wrongly_localized_share", JsonArray(wrongly_share)}};
  }
};

double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? NAN : sum / static_cast<double>(v.size());
}

// One run's figures against a truth other than the world's (named by 'against').
void PrintRun(std::uint64_t seed, const char* against, const RunFigures& f) {
  std::printf("seed %llu %s: tracking %.3f m, %.2f deg; global %s, wrongly localized at %d\n",
              static_cast<unsigned long long>(seed), against, f.tracking.mean_position,
              f.tracking.mean_heading * 180.0 / std::numbers::pi, ConvergenceText(f).c_str(), f.wrongly);
}

// The means over all runs against such a truth.
void PrintSeries(const char* against, const FigureSeries& f, int runs) {
  std::printf("%-21s tracking %.3f m, %.2f deg; global converged in %zu of %d runs, mean %.1f m driven; "
              "wrongly localized at %.1f %% of the scans\n",
              against, Mean(f.position), Mean(f.heading) * 180.0 / std::numbers::pi, f.converge.size(), runs,
              Mean(f.converge), 100.0 * Mean(f.wrongly_share));
}

}  // namespace

int RunLocalizeExperiment(CliArgs& cli) {
  const bool help = cli.Flag("--help");
  const std::optional<WorldChoice> world = help ? std::nullopt : ChooseWorld(cli, "office");
  LocalizationTourOptions options;
  const int runs = cli.Int("--runs", 1);
  const auto first_seed = static_cast<std::uint64_t>(cli.Int("--seed", 1));
  options.distance = cli.Double("--distance", options.distance);
  options.kidnap_after = cli.Double("--kidnap-after", 0.0);
  if (const auto kidnap = cli.Value("--kidnap-pose")) {
    const std::optional<Pose2D> pose = ParsePose(*kidnap);
    if (!pose) cli.AddError("--kidnap-pose needs X,Y,THETA, got '" + *kidnap + "'");
    else options.kidnap_pose = *pose;
  }
  const std::optional<std::string> map_path = cli.Value("--map");
  const bool mapping = cli.Flag("--mapping");
  options.look_around = !cli.Flag("--no-look-around");
  const std::optional<std::string> trace = cli.Value("--trace");
  const std::optional<std::string> json_path = cli.Value("--json");
  for (const std::string& assignment : cli.Values("--set")) {
    const auto eq = assignment.find('=');
    const std::string error = eq == std::string::npos ? "--set needs NAME=VALUE, got '" + assignment + "'"
                                                      : SetMclOption(options.mcl, assignment.substr(0, eq), assignment.substr(eq + 1));
    if (!error.empty()) cli.AddError(error);
  }
  if (help) {
    std::printf("%s", kUsage);
    for (const std::string& name : MclOptionNames()) std::printf("  %s\n", name.c_str());
    return 0;
  }
  if (runs < 1) cli.AddError("--runs must be at least 1");
  if (!cli.ok() || !world) {
    std::fprintf(stderr, "%s%s", cli.error().c_str(), kUsage);
    return 2;
  }

  try {
    const OccupancyGrid map = map_path ? LoadMap(*map_path) : world->world.ToGrid();
    // A map an earlier session built may sit off the world as a whole; the localizer can only be
    // as right as its map, so with --map the figures are also taken in the map's own frame.
    std::optional<MapAlignment> alignment;
    if (map_path) alignment = AlignMap(map, world->world.ToGrid());
    std::optional<MapLocalFrame> local_frame;
    if (map_path && std::filesystem::exists(MappingTrajectoryPath(*map_path))) {
      local_frame.emplace(LoadMappingTrajectory(MappingTrajectoryPath(*map_path)));
    }
    // Against the true pose; in the map's own frame; where the map has the place.
    FigureSeries truth_figures, map_figures, local_figures;
    std::vector<double> mcl_cpu, map_cpu, recover;
    int unrecovered = 0;
    std::vector<LocalizationSample> last_global;
    std::printf("%s, %d run(s) of %.0f m%s%s\n", world->path.c_str(), runs, options.distance, map_path ? ", on " : "",
                map_path ? map_path->c_str() : "");
    if (alignment) {
      std::printf("the map laid onto the world: its middle moved %.3f m and turned %.2f deg (Psi %.3f as it lies, %.3f laid onto it)\n",
                  alignment->centre_shift, alignment->move.theta * 180.0 / std::numbers::pi, alignment->psi,
                  alignment->laid_psi);
    }
    for (int r = 0; r < runs; ++r) {
      options.seed = first_seed + static_cast<std::uint64_t>(r);
      options.global = false;
      options.measure_mapping = mapping;
      const LocalizationTourResult track = RunLocalizationTour(world->world, map, world->start, options);
      const double track_until = options.kidnap_after > 0.0 ? options.kidnap_after : track.distance + 1.0;
      std::vector<LocalizationSample> before;
      for (const LocalizationSample& s : track.samples) {
        if (s.distance < track_until) before.push_back(s);
      }
      mcl_cpu.push_back(track.localizer_cpu_ms_per_scan);
      if (mapping) map_cpu.push_back(track.mapping_cpu_ms_per_scan);
      if (options.kidnap_after > 0.0) {
        const std::optional<double> back = ConvergenceDistance(track.samples, kConverged, options.kidnap_after);
        if (back) recover.push_back(*back);
        else ++unrecovered;
        std::printf("seed %llu kidnapped after %.0f m: %s\n", static_cast<unsigned long long>(options.seed),
                    options.kidnap_after, back ? ("relocalized within " + std::to_string(*back) + " m").c_str() : "not relocalized");
      }
      LocalizationTourOptions global = options;
      global.global = true;
      global.kidnap_after = 0.0;
      global.measure_mapping = false;
      const LocalizationTourResult found = RunLocalizationTour(world->world, map, world->start, global);
      last_global = found.samples;

      const RunFigures f = Measure(before, found.samples);
      truth_figures.Add(f);
      std::printf("seed %llu tracking: %.3f m, %.2f deg mean error (max %.2f m), particles %d..%d, %.2f ms CPU/scan",
                  static_cast<unsigned long long>(options.seed), f.tracking.mean_position,
                  f.tracking.mean_heading * 180.0 / std::numbers::pi, f.tracking.max_position, track.min_particles,
                  track.max_particles, track.localizer_cpu_ms_per_scan);
      if (mapping) std::printf(" (mapping filter %.2f ms)", track.mapping_cpu_ms_per_scan);
      std::printf("\n");
      std::printf("seed %llu global: %s, localized at %d of %zu scans (wrongly at %d), %.2f ms CPU/scan\n",
                  static_cast<unsigned long long>(options.seed), ConvergenceText(f).c_str(), f.localized,
                  found.samples.size(), f.wrongly, found.localizer_cpu_ms_per_scan);
      if (alignment) {
        const RunFigures m = Measure(InMapFrame(before, alignment->move), InMapFrame(found.samples, alignment->move));
        map_figures.Add(m);
        PrintRun(options.seed, "in the map's frame", m);
      }
      if (local_frame) {
        const RunFigures l = Measure(InMapLocally(before, *local_frame), InMapLocally(found.samples, *local_frame));
        local_figures.Add(l);
        PrintRun(options.seed, "where the map has it", l);
      }
    }
    const FigureSeries& t = truth_figures;
    std::printf("mean tracking error   %.3f m, %.2f deg\n", Mean(t.position), Mean(t.heading) * 180.0 / std::numbers::pi);
    std::printf("global localization   converged in %zu of %d runs, mean %.1f m driven; wrongly localized at %.1f %% of the scans\n",
                t.converge.size(), runs, Mean(t.converge), 100.0 * Mean(t.wrongly_share));
    if (alignment) PrintSeries("in the map's frame", map_figures, runs);
    if (local_frame) PrintSeries("where the map has it", local_figures, runs);
    if (options.kidnap_after > 0.0) std::printf("kidnapping            recovered in %zu of %d runs, mean %.1f m driven\n", recover.size(), runs, Mean(recover));
    std::printf("CPU per scan          %.2f ms localizing", Mean(mcl_cpu));
    if (mapping) std::printf(", %.2f ms mapping", Mean(map_cpu));
    std::printf("\n");
    if (trace) WriteTrace(*trace, last_global);
    if (json_path) {
      std::vector<std::pair<std::string, std::string>> members{{"world", JsonString(world->path)},
                                                               {"map", JsonString(map_path ? *map_path : world->path)},
                                                               {"runs", JsonNumber(runs)}};
      for (auto& m : truth_figures.Json("")) members.push_back(std::move(m));
      members.insert(members.end(), {{"kidnap_recovered_after_m", JsonArray(recover)},
                                     {"kidnap_not_recovered", JsonNumber(unrecovered)},
                                     {"localizer_cpu_ms_per_scan", JsonArray(mcl_cpu)},
                                     {"mapping_cpu_ms_per_scan", JsonArray(map_cpu)}});
      for (auto& m : map_figures.Json("map_frame_")) members.push_back(std::move(m));
      if (local_frame) {
        for (auto& m : local_figures.Json("map_local_")) members.push_back(std::move(m));
      }
      WriteJsonFile(*json_path, JsonObject(members));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pslam experiment localize: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
