// `pslam run`: maps a CARMEN log with the particle filter and writes the trajectory and the map.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "cli_args.hpp"
#include "commands.hpp"
#include "experiment_common.hpp"
#include "pslam/eval/trajectory_io.hpp"
#include "pslam/experiment/log_run.hpp"
#include "hypotheses_json.hpp"
#include "pslam/filter/divergence_monitor.hpp"
#include "pslam/slam/pslam.hpp"
#include "pslam/io/carmen_read_summary.hpp"
#include "pslam/io/carmen_reader.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam run --log FILE [--particles N] [--seed S] [--threads T] [--trajectory OUT.txt]\n"
    "                 [--map OUT_PREFIX] [--processed-trajectory OUT.txt] [--strict] [--quiet]\n"
    "                 [--raw-odometry] [--no-predict] [--no-recovery] [--similarity-threshold PSI]\n"
    "                 [--prediction-range M] [--hypotheses OUT.json] [--merged-map OUT_PREFIX]\n"
    "                 [--prior-map MAP.yaml --initial-pose X,Y,THETA] [--set NAME=VALUE ...]\n"
    "  Maps a CARMEN log. --map writes OUT_PREFIX.pgm, .yaml and .png; --trajectory writes one line\n"
    "  'timestamp x y theta' per laser scan of the log; --processed-trajectory only the scans at which\n"
    "  the filter updated. --strict stops at the first corrupt line\n"
    "  (default: skip and count it). ODOM steps that moved forward while the logged velocity was\n"
    "  backwards are re-integrated backwards; --raw-odometry keeps the poses as logged. --set tunes any filter option, e.g. --set linear_update=0.5,\n"
    "  or a threshold of the lost-filter warning, e.g. --set divergence.score_lost=0.02; 'pslam run\n"
    "  --help' lists them. A warning goes to stderr whenever the filter looks degraded or lost.\n"
    "  Loop closure is on (--set loop_closure.enabled=false turns it off), and so is tracking's second\n"
    "  start from 20 cm cells (--set tracking_match.second_start_level=-1 turns it off).\n"
    "  P-SLAM predicts the structure ahead of the robot (the target is the frontier it heads toward)\n"
    "  and weighs particles with the predictions; --no-predict runs the plain RBPF, --no-recovery\n"
    "  keeps predictions in use even when hit ratios say they are wrong. --hypotheses writes every\n"
    "  hypothesis as JSON, --merged-map the map with the predictions not refuted merged in.\n"
    "  --prior-map extends a map_server map: every particle starts from it, the first scan matched\n"
    "  to it near --initial-pose (its frame), and what the log sees overwrites what changed (the\n"
    "  prior's confidence is capped at --set prior_max_probability=P, default 0.9; 1 keeps it; its\n"
    "  floor behind a surface that is new is forgotten up to --set prior_forget_depth=M, default 1).\n";

double PeakRssMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled) {}
  void Show(double fraction, int scans) {
    if (!enabled_) return;
    const int percent = static_cast<int>(fraction * 100.0);
    if (percent == last_percent_) return;
    last_percent_ = percent;
    constexpr int kWidth = 40;
    const int filled = percent * kWidth / 100;
    std::fprintf(stderr, "\r[%s%s] %3d%%  %d scans", std::string(static_cast<std::size_t>(filled), '#').c_str(),
                 std::string(static_cast<std::size_t>(kWidth - filled), '.').c_str(), percent, scans);
    std::fflush(stderr);
  }
  void Finish() {
    if (enabled_) std::fprintf(stderr, "\n");
  }
  // Ends the bar's line before other output; the bar is drawn again at the next Show.
  void Interrupt() {
    if (!enabled_ || last_percent_ < 0) return;
    std::fprintf(stderr, "\n");
    last_percent_ = -1;
  }

 private:
  bool enabled_;
  int last_percent_ = -1;
};

constexpr const char* kDivergencePrefix = "divergence.";

// Tells the operator when the filter starts to look lost, and when it looks fine again.
void ReportTracking(const DivergenceMonitor& monitor, double log_start) {
  const double since_start = monitor.changed_at_time() - log_start;
  if (monitor.state() == TrackingState::kOk) {
    std::fprintf(stderr, "note: filter tracking ok again at scan %d, %.1f s into the log\n", monitor.changed_at_scan(),
                 since_start);
  } else {
    std::fprintf(stderr, "warning: filter %s at scan %d, %.1f s into the log: %s\n", TrackingStateName(monitor.state()),
                 monitor.changed_at_scan(), since_start, monitor.reason().c_str());
  }
}

}  // namespace

int RunRunCommand(const std::vector<std::string>& args) {
  CliArgs cli(args);
  const auto log_path = cli.Value("--log");
  PSlamOptions pslam_options;
  pslam_options.heading_targets = true;  // a log has no planner
  RbpfOptions& options = pslam_options.filter;
  options.particles = cli.Int("--particles", options.particles);
  options.seed = static_cast<std::uint64_t>(cli.Int("--seed", static_cast<int>(options.seed)));
  options.threads = cli.Int("--threads", options.threads);
  options.loop_closure.enabled = true;  // --set loop_closure.enabled=false turns it off
  // Tracking's 40 cm match now and then settles on a wrong optimum where a log's odometry lags its
  // laser in a turn; a second start from 20 cm cells mends that (ACES: 9 of 10 seeds at or below
  // Cartographer, 2 before). In simulated explorations it cost accuracy (the office drifted
  // from 0.082 to 0.111 m), and a server session exploring the simulator stopped at 65 % of a
  // small world, so only log mapping uses it (docs/loop-closure.md).
  options.tracking_match.second_start_level = 2;
  pslam_options.predict = !cli.Flag("--no-predict");
  options.recovery = !cli.Flag("--no-recovery");
  pslam_options.predictor.similarity_threshold =
      cli.Double("--similarity-threshold", pslam_options.predictor.similarity_threshold);
  pslam_options.predictor.region_size_m = cli.Double("--prediction-range", pslam_options.predictor.region_size_m);
  const auto hypotheses_path = cli.Value("--hypotheses");
  const auto merged_prefix = cli.Value("--merged-map");
  const auto trajectory_path = cli.Value("--trajectory");
  const auto processed_path = cli.Value("--processed-trajectory");
  const auto map_prefix = cli.Value("--map");
  const bool strict = cli.Flag("--strict");
  const bool raw_odometry = cli.Flag("--raw-odometry");
  const bool quiet = cli.Flag("--quiet");
  const auto prior_path = cli.Value("--prior-map");
  if (const auto text = cli.Value("--initial-pose")) {
    const auto pose = ParsePose(*text);
    if (!pose) cli.AddError("--initial-pose needs X,Y,THETA (metres, radians), got '" + *text + "'");
    else options.initial_pose = *pose;
    if (!prior_path) cli.AddError("--initial-pose is for --prior-map (a new map starts at the origin)");
  }
  DivergenceOptions divergence;
  for (const std::string& assignment : cli.Values("--set")) {
    const auto eq = assignment.find('=');
    const std::string name = assignment.substr(0, eq);
    std::string error;
    if (eq == std::string::npos) error = "--set needs NAME=VALUE, got '" + assignment + "'";
    else if (name.starts_with(kDivergencePrefix)) {
      error = SetDivergenceOption(divergence, name.substr(std::string(kDivergencePrefix).size()), assignment.substr(eq + 1));
      if (!error.empty()) error = "lost-filter warning: " + error;
    } else {
      error = SetRbpfOption(options, name, assignment.substr(eq + 1));
    }
    if (!error.empty()) cli.AddError(error);
  }
  if (cli.Flag("--help")) {
    std::cout << kUsage << "filter options (--set):\n";
    for (const auto& name : RbpfOptionNames()) std::cout << "  " << name << "\n";
    for (const auto& name : DivergenceOptionNames()) std::cout << "  " << kDivergencePrefix << name << "\n";
    return 0;
  }
  if (const auto problem = ValidatePredictorOptions(pslam_options.predictor)) cli.AddError(*problem);
  if (!cli.ok() || !log_path || options.particles < 1) {
    std::cerr << cli.error() << kUsage;
    return 2;
  }

  try {
    if (prior_path) {
      auto prior = std::make_shared<OccupancyGrid>(LoadMap(*prior_path));
      options.resolution = prior->resolution();
      options.prior_map = std::move(prior);
    }
    CarmenReader reader(*log_path, CarmenReaderOptions{.strict = strict, .repair_reversed_odometry = !raw_odometry});
    ScanStream scans(reader);
    PSlam slam(pslam_options);
    const Rbpf& filter = slam.filter();
    DivergenceMonitor monitor(options.particles, divergence);
    int warnings = 0, lost = 0;
    std::vector<std::string> stamps;
    ProgressBar progress(!quiet && isatty(STDERR_FILENO));
    const auto start = std::chrono::steady_clock::now();
    double first_time = 0.0, last_time = 0.0;
    while (auto scan = scans.Next()) {
      if (stamps.empty()) first_time = scan->timestamp;
      last_time = scan->timestamp;
      stamps.push_back(scan->timestamp_text);
      const PSlamStep step = slam.AddScan(*scan);
      RequireMapWithinLimits(filter.best().map, static_cast<int>(stamps.size()), scan->timestamp_text);
      if (monitor.Add(step.filter, *scan)) {
        progress.Interrupt();
        ReportTracking(monitor, first_time);
        if (monitor.state() != TrackingState::kOk) ++warnings;
        if (monitor.state() == TrackingState::kLost) ++lost;
      }
      progress.Show(reader.progress(), static_cast<int>(stamps.size()));
    }
    progress.Finish();
    for (const auto& e : reader.stats().first_errors) std::fprintf(stderr, "warning: %s\n", e.c_str());
    RequireScans(reader.stats(), *log_path);
    slam.FlushPredictions();
    slam.FlushLoopClosure();
    slam.ScoreHypotheses();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    if (trajectory_path) {
      const std::vector<Pose2D> poses = filter.Trajectory();
      std::vector<StampedPose> out;
      out.reserve(poses.size());
      for (std::size_t i = 0; i < poses.size(); ++i) out.push_back({stamps[i], 0.0, poses[i]});
      WriteTrajectory(*trajectory_path, out);
    }
    if (processed_path) {
      const std::vector<Pose2D> poses = filter.Trajectory();
      std::vector<StampedPose> out;
      for (int i : filter.UpdateScanIndices()) out.push_back({stamps[static_cast<std::size_t>(i)], 0.0, poses[static_cast<std::size_t>(i)]});
      WriteTrajectory(*processed_path, out);
    }
    if (map_prefix) SaveMap(filter.best().map, *map_prefix);
    if (merged_prefix) SaveMap(slam.MergedMap(), *merged_prefix);
    if (hypotheses_path) WriteHypothesesJson(*hypotheses_path, slam);

    const RbpfStats& s = filter.stats();
    const CarmenReadStats& rs = reader.stats();
    const double duration = last_time - first_time;
    std::printf("scans processed   %d (%d filter updates)\n", s.scans, s.updates);
    std::printf("corrupt lines     %zu skipped\n", rs.skipped_corrupt);
    std::printf("unknown records   %zu ignored%s\n", rs.ignored_unknown,
                rs.ignored_unknown ? (" (" + DescribeUnknownTypes(rs) + ")").c_str() : "");
    std::printf("late records      %zu dropped (out of time order by more than the reorder window)\n", rs.dropped_late);
    std::printf("no odometry       %zu scans (no robot pose in the line and no ODOM to take one from)\n",
                scans.scans_without_odometry());
    std::printf("odometry repair   %zu ODOM steps moved forward while backing up; re-integrated backwards%s\n",
                rs.repaired_odometry_steps, raw_odometry ? " (off: --raw-odometry)" : "");
    std::printf("particles         %d on %d threads\n", options.particles, options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency()));
    std::printf("wall time         %.2f s\n", wall);
    std::printf("scans/s           %.1f\n", wall > 0 ? s.scans / wall : 0.0);
    std::printf("real-time factor  %.1fx (log spans %.1f s)\n", wall > 0 ? duration / wall : 0.0, duration);
    std::printf("peak memory       %.1f MiB\n", PeakRssMiB());
    std::printf("resamplings       %d\n", s.resamplings);
    if (const LoopCloser* loops = filter.loop_closer()) {
      const LoopClosureStats& l = loops->stats();
      std::printf("loop closure      %d closures in %d searches (%d ambiguous, %d checks with a rival elsewhere,\n"
                  "                  %d outliers), %d optimisations, %d map rebuilds; %.1f s searching,\n"
                  "                  %.1f s optimising, %.1f s rebuilding\n",
                  l.closures, l.searches, l.ambiguous, l.rivalled, l.outliers, l.optimizations, l.rebuilds, l.search_ms / 1e3,
                  l.optimize_ms / 1e3, l.rebuild_ms / 1e3);
    }
    std::printf("tracking warnings %d (%d lost), %s at the end\n", warnings, lost, TrackingStateName(monitor.state()));
    if (pslam_options.predict) {
      const PSlamStats p = slam.stats();
      std::printf("predictions       %d targets, %d predicted, %d hypotheses (%d confirmed, %d refuted, %d expired)\n",
                  p.targets, p.predictions_made, p.hypotheses, p.confirmed, p.refuted, p.expired);
      std::printf("prediction time   %.1f ms mean, %.1f ms max\n",
                  p.outcomes.predictions ? p.outcomes.total_ms / static_cast<double>(p.outcomes.predictions) : 0.0,
                  p.max_prediction_ms);
      std::printf("no hypothesis     %llu no control point, %llu too little structure, %llu no reference corner,\n"
                  "                  %llu below the similarity threshold, %llu ambiguous, %llu nothing to predict\n",
                  static_cast<unsigned long long>(p.outcomes.no_control_point),
                  static_cast<unsigned long long>(p.outcomes.too_little_structure),
                  static_cast<unsigned long long>(p.outcomes.no_reference_corner),
                  static_cast<unsigned long long>(p.outcomes.below_threshold),
                  static_cast<unsigned long long>(p.outcomes.ambiguous),
                  static_cast<unsigned long long>(p.outcomes.nothing_to_predict));
      std::printf("updates weighed   %d with hypothesis points, %d used them (hit-ratio recovery %s)\n",
                  s.updates_with_hypothesis_points, s.updates_using_predictions, options.recovery ? "on" : "off");
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "pslam run: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace pslam
