// `pslam experiment NAME`: the experiments of the P-SLAM paper's section V, one file each.
#include <cstdio>
#include <string>
#include <vector>

#include "cli_args.hpp"
#include "commands.hpp"
#include "experiment_common.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam experiment NAME [options] [--json OUT] [--quiet]\n"
    "  explore      time saved by skipping predicted regions (maze; paper Sec. V-A1)\n"
    "  hypotheses   how right the hypotheses are (office; paper Sec. V-A2, Fig. 10)\n"
    "  particles    P-SLAM vs the plain RBPF on the Intel log: KL of eq. 24 and relative pose error\n"
    "  latency      time of one prediction as the map grows\n"
    "  localize     Monte Carlo localization of a simulated robot on its world's map\n"
    "  extend       extending a first map on a world whose walls moved since (lifelong mapping)\n"
    "Run 'pslam experiment NAME --help' for the options of one.\n";

}  // namespace

int RunExperimentCommand(const std::vector<std::string>& args) {
  const std::string name = args.empty() ? "" : args.front();
  CliArgs cli(std::vector<std::string>(args.begin() + (args.empty() ? 0 : 1), args.end()));
  if (name == "explore") return RunExploreExperiment(cli);
  if (name == "hypotheses") return RunHypothesesExperiment(cli);
  if (name == "particles") return RunParticlesExperiment(cli);
  if (name == "latency") return RunLatencyExperiment(cli);
  if (name == "localize") return RunLocalizeExperiment(cli);
  if (name == "extend") return RunExtendExperiment(cli);
  const bool help = name.empty() || name == "--help" || name == "-h";
  if (!help) std::fprintf(stderr, "unknown experiment '%s'\n", name.c_str());
  std::fprintf(help ? stdout : stderr, "%s", kUsage);
  return help ? 0 : 2;
}

}  // namespace pslam
