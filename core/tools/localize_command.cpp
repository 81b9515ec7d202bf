// `pslam localize`: Monte Carlo localization of a CARMEN log on a fixed map.
#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_args.hpp"
#include "commands.hpp"
#include "experiment_common.hpp"
#include "pslam/eval/trajectory_io.hpp"
#include "pslam/io/carmen_read_summary.hpp"
#include "pslam/io/carmen_reader.hpp"
#include "pslam/io/map_io.hpp"
#include "pslam/localize/monte_carlo_localizer.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam localize --map MAP.yaml --log FILE [--initial-pose X,Y,THETA] [--initial-std M,RAD]\n"
    "                      [--global] [--trajectory OUT.txt] [--seed S] [--strict] [--raw-odometry]\n"
    "                      [--set NAME=VALUE ...]\n"
    "  Localizes the robot of a CARMEN log on a map_server map with Monte Carlo localization\n"
    "  (likelihood field, KLD-adaptive particle count, random injection after kidnapping). With\n"
    "  --initial-pose (map frame) the particles start around it with standard deviations\n"
    "  --initial-std (default 0.25,0.2); without it, or with --global, they start spread over the\n"
    "  map's free space (global localization). --trajectory writes one line 'timestamp x y theta'\n"
    "  per laser scan: the estimate (mean of the heaviest particle cluster). ODOM steps that moved\n"
    "  forward while the logged velocity was backwards are re-integrated backwards; --raw-odometry\n"
    "  keeps the poses as logged. --set tunes a localization option:\n";

double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::optional<std::pair<double, double>> ParsePair(const std::string& text) {
  std::istringstream in(text);
  double a = 0.0, b = 0.0;
  char comma = 0;
  if (!(in >> a >> comma >> b) || comma != ',') return std::nullopt;
  in >> std::ws;
  if (!in.eof() || !std::isfinite(a) || !std::isfinite(b) || a < 0.0 || b < 0.0) return std::nullopt;
  return std::make_pair(a, b);
}

}  // namespace

int RunLocalizeCommand(const std::vector<std::string>& args) {
  CliArgs cli(args);
  const auto map_path = cli.Value("--map");
  const auto log_path = cli.Value("--log");
  const auto trajectory_path = cli.Value("--trajectory");
  const bool global = cli.Flag("--global");
  const bool strict = cli.Flag("--strict");
  const bool raw_odometry = cli.Flag("--raw-odometry");
  MclOptions options;
  options.seed = static_cast<std::uint64_t>(cli.Int("--seed", static_cast<int>(options.seed)));
  std::optional<Pose2D> initial;
  if (const auto text = cli.Value("--initial-pose")) {
    initial = ParsePose(*text);
    if (!initial) cli.AddError("--initial-pose needs X,Y,THETA (metres, radians), got '" + *text + "'");
  }
  std::pair<double, double> spread{0.25, 0.2};
  if (const auto text = cli.Value("--initial-std")) {
    const auto parsed = ParsePair(*text);
    if (!parsed) cli.AddError("--initial-std needs M,RAD (two non-negative numbers), got '" + *text + "'");
    else spread = *parsed;
  }
  for (const std::string& assignment : cli.Values("--set")) {
    const auto eq = assignment.find('=');
    const std::string error = eq == std::string::npos ? "--set needs NAME=VALUE, got '" + assignment + "'"
                                                      : SetMclOption(options, assignment.substr(0, eq), assignment.substr(eq + 1));
    if (!error.empty()) cli.AddError(error);
  }
  if (cli.Flag("--help")) {
    std::cout << kUsage;
    for (const std::string& name : MclOptionNames()) std::cout << "  " << name << "\n";
    return 0;
  }
  if (global && initial) cli.AddError("--global and --initial-pose exclude each other");
  if (const std::string problem = ValidateMclOptions(options); !problem.empty()) cli.AddError(problem);
  if (!cli.ok() || !map_path || !log_path) {
    std::cerr << cli.error() << (map_path && log_path ? "" : "--map and --log are required\n") << kUsage;
    return 2;
  }

  try {
    const OccupancyGrid map = LoadMap(*map_path);
    MonteCarloLocalizer mcl(map, options);
    if (initial) {
      const double p2 = spread.first * spread.first, t2 = spread.second * spread.second;
      mcl.SetPose(*initial, Eigen::Vector3d(p2, p2, t2).asDiagonal());
    } else {
      mcl.StartGlobal();
    }
    CarmenReader reader(*log_path, CarmenReaderOptions{.strict = strict, .repair_reversed_odometry = !raw_odometry});
    ScanStream scans(reader);
    std::vector<StampedPose> trajectory;
    const auto wall_start = std::chrono::steady_clock::now();
    double cpu = 0.0, first_time = 0.0, last_time = 0.0, particle_sum = 0.0;
    std::optional<double> localized_at;  // log time of the first localized update
    int localized_scans = 0;
    while (auto scan = scans.Next()) {
      if (trajectory.empty()) first_time = scan->timestamp;
      last_time = scan->timestamp;
      const double before = ThreadCpuSeconds();
      const MclUpdate update = mcl.AddScan(*scan);
      cpu += ThreadCpuSeconds() - before;
      particle_sum += update.particles;
      if (update.localized) {
        ++localized_scans;
        if (!localized_at) localized_at = scan->timestamp - first_time;
      }
      trajectory.push_back({scan->timestamp_text, scan->timestamp, update.estimate});
    }
    for (const auto& e : reader.stats().first_errors) std::fprintf(stderr, "warning: %s\n", e.c_str());
    RequireScans(reader.stats(), *log_path);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (trajectory_path) WriteTrajectory(*trajectory_path, trajectory);

    const MclStats& s = mcl.stats();
    const MclUpdate& end = mcl.last();
    std::printf("scans processed   %d (%d filter updates, %d resamplings)\n", s.scans, s.updates, s.resamplings);
    std::printf("corrupt lines     %zu skipped\n", reader.stats().skipped_corrupt);
    std::printf("start             %s\n", initial ? "initial pose given" : "global localization");
    std::printf("particles         %d to %d, %.0f on average\n", s.min_particles_seen, s.max_particles_seen,
                s.scans ? particle_sum / s.scans : 0.0);
    std::printf("random injection  %lld particles\n", s.injected);
    std::printf("walls added       %d cells the map never saw (fill_unknown)\n", mcl.unmapped_obstacles());
    std::printf("CPU per scan      %.3f ms (%.3f ms per update)\n", s.scans ? 1e3 * cpu / s.scans : 0.0,
                s.updates ? 1e3 * cpu / s.updates : 0.0);
    std::printf("wall time         %.2f s (log spans %.1f s)\n", wall, last_time - first_time);
    if (localized_at) std::printf("localized         first after %.1f s of the log; at %.0f %% of the scans\n", *localized_at,
                                  100.0 * localized_scans / std::max(1, s.scans));
    else std::printf("localized         never\n");
    std::printf("at the end        %s, %d clusters, heaviest holds %.2f of the weight, spread %.3f m, %.2f deg\n",
                end.localized ? "localized" : "not localized", end.clusters, end.cluster.weight, end.cluster.position_std,
                end.cluster.heading_std * 180.0 / std::numbers::pi);
    std::printf("final estimate    %.3f %.3f %.4f\n", end.estimate.x, end.estimate.y, end.estimate.theta);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "pslam localize: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace pslam
