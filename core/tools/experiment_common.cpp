#include "experiment_common.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "pslam/experiment/map_similarity.hpp"
#include "pslam/filter/rbpf_options.hpp"
#include "pslam/sim/floorplan.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

namespace fs = std::filesystem;

std::string DefaultWorldPath(const std::string& name) {
  const fs::path relative = fs::path("core") / "worlds" / (name + ".yaml");
  if (fs::exists(relative)) return relative.string();
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path beside = exe.parent_path().parent_path().parent_path() / relative;  // build/bin/pslam
    if (fs::exists(beside)) return beside.string();
  }
  return relative.string();  // LoadWorld names it in the error
}

}  // namespace

std::optional<Pose2D> ParsePose(const std::string& text) {
  std::istringstream in(text);
  double x = 0.0, y = 0.0, theta = 0.0;
  char c1 = 0, c2 = 0;
  if (!(in >> x >> c1 >> y >> c2 >> theta) || c1 != ',' || c2 != ',') return std::nullopt;
  in >> std::ws;
  if (!in.eof()) return std::nullopt;
  return Pose2D(x, y, theta);
}

std::optional<WorldChoice> ChooseWorld(CliArgs& cli, const std::string& default_name) {
  const std::optional<std::string> world_flag = cli.Value("--world");
  const std::optional<std::string> start_flag = cli.Value("--start");
  const std::string path = world_flag ? *world_flag : DefaultWorldPath(default_name);
  if (!fs::exists(path)) {
    cli.AddError("world file not found: " + path + " (run from the repository root, or give --world FILE.yaml)");
    return std::nullopt;
  }
  std::optional<Pose2D> start;
  if (start_flag) {
    start = ParsePose(*start_flag);
    if (!start) cli.AddError("--start needs X,Y,THETA (metres, radians), got '" + *start_flag + "'");
  } else {
    start = ReadStartPose(path);
    if (!start) cli.AddError(path + " has no '# start: x, y, theta' line: give --start X,Y,THETA");
  }
  if (!start) return std::nullopt;
  try {
    return WorldChoice{path, LoadWorld(path), *start};
  } catch (const std::exception& e) {
    cli.AddError(e.what());
    return std::nullopt;
  }
}

const char* const kGeneratedWorldsUsage =
    "  --generated FAMILY [--count N (1)] [--first-seed S (1)]: N generated floor plans instead of --world\n"
    "    (office, hotel, hospital, school, maze, hall, open, mixed; see 'pslam worlds generate')\n";

std::vector<WorldChoice> ChooseWorlds(CliArgs& cli, const std::string& default_name) {
  const std::optional<std::string> family_name = cli.Value("--generated");
  const int count = cli.Int("--count", 1), first_seed = cli.Int("--first-seed", 1);
  std::vector<WorldChoice> worlds;
  if (!family_name) {
    if (auto world = ChooseWorld(cli, default_name)) worlds.push_back(std::move(*world));
    return worlds;
  }
  const auto family = ParseFloorPlanFamily(*family_name);
  if (!family) cli.AddError("--generated: unknown family '" + *family_name + "'");
  if (count < 1) cli.AddError("--count must be at least 1");
  if (first_seed < 0) cli.AddError("--first-seed must not be negative");
  if (cli.Value("--world")) cli.AddError("--generated and --world exclude each other");
  if (!family || count < 1 || first_seed < 0) return worlds;
  for (int i = 0; i < count; ++i) {
    FloorPlan plan = GenerateFloorPlan(*family, static_cast<std::uint64_t>(first_seed + i));
    worlds.push_back({"generated:" + plan.name, std::move(plan.world), plan.start});
  }
  return worlds;
}

Spread SpreadOf(const std::vector<double>& values) {
  Spread s;
  double sum = 0.0, sum2 = 0.0;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    s.min = s.n ? std::min(s.min, v) : v;
    s.max = s.n ? std::max(s.max, v) : v;
    sum += v;
    sum2 += v * v;
    ++s.n;
  }
  if (s.n == 0) {
    s.mean = s.std = s.min = s.max = std::numeric_limits<double>::quiet_NaN();
    return s;
  }
  s.mean = sum / s.n;
  s.std = std::sqrt(std::max(0.0, sum2 / s.n - s.mean * s.mean));
  return s;
}

std::string SpreadText(const Spread& s, double scale, const char* format) {
  if (s.n == 0) return "none";
  const auto f = [&](double v) {
    char b[32];
    std::snprintf(b, sizeof b, format, v * scale);
    return std::string(b);
  };
  return f(s.mean) + " +- " + f(s.std) + " [" + f(s.min) + ", " + f(s.max) + "] (n " + std::to_string(s.n) + ")";
}

std::string SpreadJson(const Spread& s) {
  return JsonObject({{"n", JsonNumber(s.n)}, {"mean", JsonNumber(s.mean)}, {"std", JsonNumber(s.std)},
                     {"min", JsonNumber(s.min)}, {"max", JsonNumber(s.max)}});
}

std::string SharedDataDir() {
  const char* env = std::getenv("PSLAM_DATA_DIR");
  return env != nullptr && *env != '\0' ? env : "../shared/data";
}

const char* const kExplorationFlagsUsage =
    "  --seed S (1)  --particles N (30)  --threads T (0: all cores)  --time-limit S (simulated)\n"
    "  --similarity-threshold PSI (0.6, the paper's simulations)  --prediction-range M (10)\n"
    "  --ambiguity-margin M (0.1; 0: the paper's best match, no ambiguity rule)\n"
    "  --local-refutation M (1: a hypothesis loses its cells within M of where the robot sees it\n"
    "    wrong; 0: off)\n"
    "  --drop-sealed-off (hypotheses lose predicted floor cut off from all the floor seen)\n"
    "  --control-point-range M (3: the corner nearest the target within M is the control point)\n"
    "  --degenerate-ratio R (0.15; 0: no degeneracy guard in scan matching)\n"
    "  --set NAME=VALUE (any filter option of 'pslam run --help', e.g. --set loop_closure.enabled=true)\n";

ExplorationOptions ExplorationFromCli(CliArgs& cli, double default_time_limit_s) {
  ExplorationOptions options = DefaultExplorationOptions();
  const int seed = cli.Int("--seed", 1);
  options.simulator.seed = static_cast<std::uint64_t>(seed);
  options.slam.filter.seed = static_cast<std::uint64_t>(seed);
  options.slam.filter.particles = cli.Int("--particles", options.slam.filter.particles);
  options.slam.filter.threads = cli.Int("--threads", options.slam.filter.threads);
  options.slam.predictor.similarity_threshold = cli.Double("--similarity-threshold", 0.6);
  options.slam.predictor.region_size_m = cli.Double("--prediction-range", options.slam.predictor.region_size_m);
  options.slam.predictor.control_point_range_m =
      cli.Double("--control-point-range", options.slam.predictor.control_point_range_m);
  options.slam.predictor.ambiguity_margin = cli.Double("--ambiguity-margin", options.slam.predictor.ambiguity_margin);
  options.slam.judge.local_refutation_radius_m =
      cli.Double("--local-refutation", options.slam.judge.local_refutation_radius_m);
  if (!(options.slam.judge.local_refutation_radius_m >= 0.0)) cli.AddError("--local-refutation must be 0 or more");
  if (cli.Flag("--drop-sealed-off")) options.slam.judge.drop_sealed_off = true;
  const double degenerate_ratio = cli.Double("--degenerate-ratio", options.slam.filter.tracking_match.degenerate_ratio);
  if (!(degenerate_ratio >= 0.0 && degenerate_ratio < 1.0)) cli.AddError("--degenerate-ratio must lie in [0, 1)");
  SetDegenerateRatio(options.slam.filter, degenerate_ratio);
  for (const std::string& assignment : cli.Values("--set")) {
    const auto eq = assignment.find('=');
    const std::string error = eq == std::string::npos
                                  ? "--set needs NAME=VALUE, got '" + assignment + "'"
                                  : SetRbpfOption(options.slam.filter, assignment.substr(0, eq), assignment.substr(eq + 1));
    if (!error.empty()) cli.AddError(error);
  }
  options.time_limit_s = cli.Double("--time-limit", default_time_limit_s);
  if (options.slam.filter.particles < 1) cli.AddError("--particles must be at least 1");
  if (!(options.time_limit_s > 0.0)) cli.AddError("--time-limit must be positive");
  if (const auto problem = ValidatePredictorOptions(options.slam.predictor)) cli.AddError(*problem);
  return options;
}

void ProgressLine::Show(const std::string& text, bool force) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && shown_ && now - last_ < std::chrono::milliseconds(250)) return;
  last_ = now;
  shown_ = true;
  std::fprintf(stderr, "\r%-78s", text.c_str());
  std::fflush(stderr);
}

void ProgressLine::Finish() {
  if (enabled_ && shown_) std::fprintf(stderr, "\r%78s\r", "");
  shown_ = false;
}

bool ProgressWanted(CliArgs& cli) { return !cli.Flag("--quiet") && isatty(STDERR_FILENO); }

std::vector<std::vector<HypothesisCell>> AcceptedCellsInWorld(const ExplorationRun& run) {
  std::vector<std::vector<HypothesisCell>> out;
  const double resolution = run.options().slam.filter.resolution;
  for (std::size_t i = 0; i < run.accepted_hypotheses().size(); ++i) {
    out.push_back(TransformCells(run.accepted_hypotheses()[i].cells, run.accepted_map_to_world()[i], resolution));
  }
  return out;
}

JudgeAgreement CountJudgedAsTruth(const ExplorationRun& run, const std::vector<double>& psi_truth) {
  JudgeAgreement agreement;
  // P-SLAM keeps its hypotheses in acceptance order, like accepted_hypotheses().
  const std::vector<Hypothesis>& judged = run.slam().hypotheses();
  for (std::size_t i = 0; i < judged.size() && i < psi_truth.size(); ++i) {
    const bool confirmed = judged[i].status == Hypothesis::Status::kConfirmed;
    if (!confirmed && judged[i].status != Hypothesis::Status::kRefuted) continue;
    if (!std::isfinite(psi_truth[i])) continue;
    ++agreement.judged;
    agreement.as_truth += confirmed == (psi_truth[i] >= run.options().slam.judge.confirm_psi);
  }
  return agreement;
}

Pose2D AcceptedMapToWorld(const ExplorationRun& run, int id) {
  for (std::size_t i = 0; i < run.accepted_hypotheses().size(); ++i) {
    if (run.accepted_hypotheses()[i].id == id) return run.accepted_map_to_world()[i];
  }
  return Pose2D();
}

ExplorationSummary RunExplorationWithProgress(ExplorationRun& run, const std::string& label, ProgressLine& progress) {
  while (!run.done()) {
    run.Step();
    char line[160];
    std::snprintf(line, sizeof line, "%s: %.0f / %.0f simulated s, %zu hypotheses", label.c_str(), run.time(),
                  run.options().time_limit_s, run.accepted_hypotheses().size());
    progress.Show(line);
  }
  progress.Finish();
  return run.Summary();
}

std::string JsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

std::string JsonString(const std::string& value) {
  std::string out = "\"";
  for (const char c : value) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string JsonArray(const std::vector<double>& values) {
  std::vector<std::string> texts;
  texts.reserve(values.size());
  for (const double v : values) texts.push_back(JsonNumber(v));
  return JsonArray(texts);
}

std::string JsonArray(const std::vector<std::string>& json_values) {
  std::string out = "[";
  for (std::size_t i = 0; i < json_values.size(); ++i) out += (i ? ", " : "") + json_values[i];
  return out + "]";
}

std::string JsonObject(const std::vector<std::pair<std::string, std::string>>& members) {
  std::string out = "{";
  for (std::size_t i = 0; i < members.size(); ++i) {
    out += (i ? ", " : "") + JsonString(members[i].first) + ": " + members[i].second;
  }
  return out + "}";
}

void WriteJsonFile(const std::string& path, const std::string& json) {
  std::ofstream out(path);
  out << json << "\n";
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace pslam
