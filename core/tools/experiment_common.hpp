#pragma once
// Shared pieces of `pslam experiment NAME`: locating worlds and data, the options every simulated
// experiment takes, a progress line for long runs, and a flat JSON writer (core has no JSON
// dependency, and the summaries are small).
#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli_args.hpp"
#include "pslam/common/pose2d.hpp"
#include "pslam/experiment/exploration_run.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

// The experiments; each returns the process exit code (0 ok, 1 failure, 2 usage error).
int RunExploreExperiment(CliArgs& cli);
int RunHypothesesExperiment(CliArgs& cli);
int RunParticlesExperiment(CliArgs& cli);
int RunLatencyExperiment(CliArgs& cli);
int RunLocalizeExperiment(CliArgs& cli);
int RunExtendExperiment(CliArgs& cli);

// "X,Y,THETA" (metres, radians); nullopt when malformed.
std::optional<Pose2D> ParsePose(const std::string& text);

// A world given by --world FILE.yaml (default core/worlds/<default_name>.yaml, looked up from the
// working directory and then from the executable's ../../), with its start pose from --start
// X,Y,THETA or the YAML's "# start:" line.
struct WorldChoice {
  std::string path;
  World world;
  Pose2D start;
};
// nullopt after adding the problem to cli's errors.
std::optional<WorldChoice> ChooseWorld(CliArgs& cli, const std::string& default_name);

// The worlds of an experiment: with --generated FAMILY, --count N (1) floor plans of that family
// (core/pslam/sim/floorplan.hpp) from --first-seed S (1) on, each named generated:FAMILY_SEED;
// else the one world of ChooseWorld. Empty after adding the problem to cli's errors.
std::vector<WorldChoice> ChooseWorlds(CliArgs& cli, const std::string& default_name);
extern const char* const kGeneratedWorldsUsage;

// A figure over a population of runs: mean, standard deviation (population), min and max of the
// finite values; n counts them.
struct Spread {
  int n = 0;
  double mean = 0.0, std = 0.0, min = 0.0, max = 0.0;
};
Spread SpreadOf(const std::vector<double>& values);
std::string SpreadText(const Spread& s, double scale = 1.0, const char* format = "%.3f");  // "m +- s [min, max] (n)"
std::string SpreadJson(const Spread& s);

// The shared data folder: $PSLAM_DATA_DIR, else ../shared/data.
std::string SharedDataDir();

// Exploration options from the flags every simulated experiment takes:
// --seed S, --particles N, --threads T, --similarity-threshold PSI, --prediction-range M,
// --time-limit S. The defaults follow the paper's simulations (Sec. V-A): threshold 0.6, d = 10 m.
ExplorationOptions ExplorationFromCli(CliArgs& cli, double default_time_limit_s);
extern const char* const kExplorationFlagsUsage;

// One progress line on stderr, redrawn at most a few times a second; silent when disabled.
class ProgressLine {
 public:
  explicit ProgressLine(bool enabled) : enabled_(enabled) {}
  void Show(const std::string& text, bool force = false);
  void Finish();

 private:
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point last_{};
};
// Enabled when stderr is a terminal and --quiet was not given.
bool ProgressWanted(CliArgs& cli);

// The accepted hypotheses of a run in the world frame (see accepted_map_to_world), and the
// transform for the hypothesis with a given id (identity if there is none).
std::vector<std::vector<HypothesisCell>> AcceptedCellsInWorld(const ExplorationRun& run);
Pose2D AcceptedMapToWorld(const ExplorationRun& run, int id);

// How often P-SLAM's judge agrees with the true world: of the hypotheses it confirmed or refuted
// (and that the truth scores), those whose verdict matches Psi vs truth >= confirm_psi.
// 'psi_truth' holds one value per accepted hypothesis, in acceptance order.
struct JudgeAgreement {
  int judged = 0;
  int as_truth = 0;
};
JudgeAgreement CountJudgedAsTruth(const ExplorationRun& run, const std::vector<double>& psi_truth);

// Runs an exploration to its end with a progress line labelled 'label'.
ExplorationSummary RunExplorationWithProgress(ExplorationRun& run, const std::string& label, ProgressLine& progress);

// Flat JSON text.
std::string JsonNumber(double value);  // null when not finite
std::string JsonString(const std::string& value);
std::string JsonArray(const std::vector<double>& values);
std::string JsonArray(const std::vector<std::string>& json_values);  // elements already JSON
std::string JsonObject(const std::vector<std::pair<std::string, std::string>>& members);  // values already JSON
// Writes 'json' and a newline to 'path'; throws std::runtime_error naming the file on failure.
void WriteJsonFile(const std::string& path, const std::string& json);

}  // namespace pslam
