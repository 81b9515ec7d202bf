// pslam: command-line entry point. Each subcommand lives in its own file.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + std::min(argc, 2), argv + argc);
  const std::string command = argc > 1 ? argv[1] : "";
  if (command == "run") return pslam::RunRunCommand(args);
  if (command == "localize") return pslam::RunLocalizeCommand(args);
  if (command == "eval") return pslam::RunEvalCommand(args);
  if (command == "experiment") return pslam::RunExperimentCommand(args);
  if (command == "worlds") return pslam::RunWorldsCommand(args);
  std::fprintf(stderr,
               "usage: pslam COMMAND [options]\n"
               "commands:\n"
               "  run    map a CARMEN log with the particle filter\n"
               "  localize  localize a CARMEN log on a fixed map (Monte Carlo localization)\n"
               "  eval   relative pose error of a trajectory, or KL divergence between two maps\n"
               "  experiment  the paper's experiments: explore, hypotheses, particles, latency\n"
               "  worlds generate  write a generated floor plan (office, hotel, ... open) as a map_server world\n"
               "Run 'pslam COMMAND --help' for the options of a command.\n");
  return command.empty() || command == "--help" || command == "-h" ? 0 : 2;
}
