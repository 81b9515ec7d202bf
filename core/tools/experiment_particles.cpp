// `pslam experiment particles`: the paper's claim that P-SLAM needs fewer particles (Sec. IV-B,
// V-B3, Fig. 16-17, on a Radish data set). On the Intel Research Lab log: P-SLAM with 40 particles,
// with and without the hit-ratio recovery, against the plain RBPF with 40 and with 200 particles.
// Map accuracy is the KL divergence of eq. 24 against a reference map built by a separate
// RBPF run with 200 particles (the paper used 1000); trajectory accuracy is the relative pose
// error against the ground-truth relations of Kuemmerle et al. 2009.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "experiment_common.hpp"
#include "pslam/eval/map_divergence.hpp"
#include "pslam/eval/relative_pose_error.hpp"
#include "pslam/experiment/log_run.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam experiment particles [--log FILE] [--relations FILE] [--particles N] [--large N]\n"
    "                                  [--reference-particles N] [--reference-map FILE.yaml]\n"
    "                                  [--search-rpe M] [--search-counts N,N,...] [--max-scans N]\n"
    "                                  [--seed S] [--threads T] [--similarity-threshold PSI]\n"
    "                                  [--out DIR] [--json OUT] [--quiet]\n"
    "  Runs P-SLAM-N with and without recovery, RBPF-N and RBPF-LARGE (N = 40, LARGE = 200) on the log\n"
    "  (default $PSLAM_DATA_DIR or ../shared/data: intel/intel.clf and intel/intel.relations) and\n"
    "  compares the KL divergence (eq. 24) against a reference map from a separate RBPF run with\n"
    "  --reference-particles (200, seed S+1000) or from --reference-map, and the relative pose error.\n"
    "  --search-rpe M also finds, for RBPF and for P-SLAM, the fewest of --search-counts particles\n"
    "  (5,10,20,40,80) whose mean translational RPE is at most M metres. --out DIR saves every map\n"
    "  and trajectory. --max-scans limits the log for quick runs.\n";

struct ParticleRun {
  std::string name;
  int particles = 0;
  bool predict = false;
  bool recovery = false;
  double kl = 0.0;
  RpeResult rpe;
  LogRunResult log;
};

std::string RunJson(const ParticleRun& r) {
  return JsonObject({{"name", JsonString(r.name)},
                     {"particles", JsonNumber(r.particles)},
                     {"predict", r.predict ? "true" : "false"},
                     {"recovery", r.recovery ? "true" : "false"},
                     {"kl", JsonNumber(r.kl)},
                     {"rpe_trans_m", JsonNumber(r.rpe.trans_mean)},
                     {"rpe_trans_std_m", JsonNumber(r.rpe.trans_std)},
                     {"rpe_rot_deg", JsonNumber(r.rpe.rot_mean_deg)},
                     {"rpe_rot_std_deg", JsonNumber(r.rpe.rot_std_deg)},
                     {"relations_used", JsonNumber(static_cast<double>(r.rpe.used))},
                     {"wall_s", JsonNumber(r.log.wall_time_s)},
                     {"hypotheses", JsonNumber(r.log.slam.hypotheses)},
                     {"predictions", JsonNumber(static_cast<double>(r.log.slam.outcomes.predictions))},
                     {"predictions_below_threshold", JsonNumber(static_cast<double>(r.log.slam.outcomes.below_threshold))},
                     {"predictions_without_control_point", JsonNumber(static_cast<double>(r.log.slam.outcomes.no_control_point))},
                     {"predictions_with_too_little_structure", JsonNumber(static_cast<double>(r.log.slam.outcomes.too_little_structure))},
                     {"updates", JsonNumber(r.log.filter.updates)},
                     {"updates_with_hypothesis_points", JsonNumber(r.log.filter.updates_with_hypothesis_points)},
                     {"updates_using_predictions", JsonNumber(r.log.filter.updates_using_predictions)}});
}

std::vector<int> ParseCounts(const std::string& text, CliArgs& cli) {
  std::vector<int> counts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      counts.push_back(std::stoi(item));
    } catch (const std::exception&) {
      cli.AddError("--search-counts needs N,N,..., got '" + text + "'");
      return {};
    }
    if (counts.back() < 1) cli.AddError("--search-counts must be positive");
  }
  return counts;
}

}  // namespace

int RunParticlesExperiment(CliArgs& cli) {
  const bool help = cli.Flag("--help");
  const std::string data = SharedDataDir() + "/intel/";
  const std::string log_path = cli.Value("--log").value_or(data + "intel.clf");
  const std::string relations_path = cli.Value("--relations").value_or(data + "intel.relations");
  const int particles = cli.Int("--particles", 40);
  const int large = cli.Int("--large", 200);
  const int reference_particles = cli.Int("--reference-particles", 200);
  const std::optional<std::string> reference_map = cli.Value("--reference-map");
  const double search_rpe = cli.Double("--search-rpe", 0.0);
  const std::vector<int> search_counts = ParseCounts(cli.Value("--search-counts").value_or("5,10,20,40,80"), cli);
  const int max_scans = cli.Int("--max-scans", 0);
  const int seed = cli.Int("--seed", 1);
  PSlamOptions base;
  base.filter.threads = cli.Int("--threads", 0);
  base.filter.seed = static_cast<std::uint64_t>(seed);
  base.predictor.similarity_threshold = cli.Double("--similarity-threshold", base.predictor.similarity_threshold);
  const std::optional<std::string> out_dir = cli.Value("--out");
  const std::optional<std::string> json_path = cli.Value("--json");
  ProgressLine progress(ProgressWanted(cli));
  if (help) {
    std::printf("%s", kUsage);
    return 0;
  }
  if (particles < 1 || large < 1 || reference_particles < 1) cli.AddError("particle counts must be positive");
  if (const auto problem = ValidatePredictorOptions(base.predictor)) cli.AddError(*problem);
  if (!cli.ok()) {
    std::fprintf(stderr, "%s%s", cli.error().c_str(), kUsage);
    return 2;
  }
  try {
    const std::vector<Relation> relations = ReadRelations(relations_path);
    if (out_dir) std::filesystem::create_directories(*out_dir);
    const auto run = [&](const std::string& name, int n, bool predict, bool recovery, std::uint64_t run_seed) {
      PSlamOptions options = base;
      options.filter.particles = n;
      options.filter.seed = run_seed;
      options.predict = predict;
      options.filter.recovery = recovery;
      ParticleRun r;
      r.name = name;
      r.particles = n;
      r.predict = predict;
      r.recovery = recovery;
      r.log = RunLog(log_path, options, [&](double fraction, int scans) {
        char line[160];
        std::snprintf(line, sizeof line, "%s: %3.0f %%, %d scans", name.c_str(), 100.0 * fraction, scans);
        progress.Show(line);
      }, max_scans);
      progress.Finish();
      r.rpe = ComputeRpe(r.log.trajectory, relations);
      if (out_dir) {
        std::string stem = name;
        for (char& c : stem) c = (c == ' ' || c == ',' || c == '/') ? '_' : c;
        SaveMap(r.log.map, *out_dir + "/" + stem);
        WriteTrajectory(*out_dir + "/" + stem + ".txt", r.log.trajectory);
      }
      return r;
    };

    OccupancyGrid reference;
    std::string reference_name;
    if (reference_map) {
      reference = LoadMap(*reference_map);
      reference_name = *reference_map;
    } else {
      reference_name = "RBPF-" + std::to_string(reference_particles) + " seed " + std::to_string(seed + 1000);
      reference = run("reference " + reference_name, reference_particles, false, false,
                      static_cast<std::uint64_t>(seed + 1000)).log.map;
    }

    const std::string n = std::to_string(particles);
    std::vector<ParticleRun> runs;
    runs.push_back(run("P-SLAM-" + n, particles, true, true, base.filter.seed));
    runs.push_back(run("P-SLAM-" + n + " no recovery", particles, true, false, base.filter.seed));
    runs.push_back(run("RBPF-" + n, particles, false, false, base.filter.seed));
    runs.push_back(run("RBPF-" + std::to_string(large), large, false, false, base.filter.seed));
    for (ParticleRun& r : runs) r.kl = ComputeMapDivergence(reference, r.log.map).kl;

    std::printf("log %s%s, reference map: %s, seed %d\n", log_path.c_str(),
                max_scans > 0 ? (" (first " + std::to_string(max_scans) + " scans)").c_str() : "",
                reference_name.c_str(), seed);
    std::printf("%-26s %9s %7s %8s %12s %14s %13s %11s %8s %7s\n", "run", "particles", "predict", "recovery",
                "KL [nats]", "RPE trans [m]", "RPE rot [deg]", "hyp/preds", "S2 used", "wall_s");
    for (const ParticleRun& r : runs) {
      const std::string hypotheses =
          std::to_string(r.log.slam.hypotheses) + "/" + std::to_string(r.log.slam.outcomes.predictions);
      std::printf("%-26s %9d %7s %8s %12.1f %8.4f±%.3f %7.3f±%.2f %11s %8d %7.1f\n", r.name.c_str(), r.particles,
                  r.predict ? "on" : "off", r.recovery ? "on" : "off", r.kl, r.rpe.trans_mean, r.rpe.trans_std,
                  r.rpe.rot_mean_deg, r.rpe.rot_std_deg, hypotheses.c_str(), r.log.filter.updates_using_predictions,
                  r.log.wall_time_s);
    }

    // The fewest particles reaching the RPE goal, for each filter: the paper's "fewer particles".
    std::vector<std::string> search_json;
    if (search_rpe > 0.0) {
      for (const bool predict : {false, true}) {
        std::vector<std::string> tried;
        int fewest = 0;
        for (const int count : search_counts) {
          const ParticleRun r = run(std::string(predict ? "P-SLAM-" : "RBPF-") + std::to_string(count) + " search",
                                    count, predict, true, base.filter.seed);
          tried.push_back(JsonObject({{"particles", JsonNumber(count)}, {"rpe_trans_m", JsonNumber(r.rpe.trans_mean)}}));
          std::printf("search %-7s %4d particles: RPE %.4f m\n", predict ? "P-SLAM" : "RBPF", count, r.rpe.trans_mean);
          if (r.rpe.trans_mean <= search_rpe) {
            fewest = count;
            break;
          }
        }
        std::printf("fewest particles for RPE <= %.3f m, %s: %s\n", search_rpe, predict ? "P-SLAM" : "RBPF",
                    fewest ? std::to_string(fewest).c_str() : "none of those tried");
        search_json.push_back(JsonObject({{"filter", JsonString(predict ? "P-SLAM" : "RBPF")},
                                          {"fewest_particles", fewest ? JsonNumber(fewest) : "null"},
                                          {"tried", JsonArray(tried)}}));
      }
    }

    if (json_path) {
      std::vector<std::string> rows;
      for (const ParticleRun& r : runs) rows.push_back(RunJson(r));
      WriteJsonFile(*json_path, JsonObject({{"experiment", JsonString("particles")},
                                            {"log", JsonString(log_path)},
                                            {"relations", JsonString(relations_path)},
                                            {"max_scans", JsonNumber(max_scans)},
                                            {"seed", JsonNumber(seed)},
                                            {"reference", JsonString(reference_name)},
                                            {"runs", JsonArray(rows)},
                                            {"search_rpe_m", JsonNumber(search_rpe)},
                                            {"search", JsonArray(search_json)}}));
    }
    return 0;
  } catch (const std::exception& e) {
    progress.Finish();
    std::fprintf(stderr, "pslam experiment particles: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
