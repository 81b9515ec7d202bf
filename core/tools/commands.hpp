#pragma once
// Subcommands of the `pslam` CLI. main.cpp dispatches on the first argument and passes the
// arguments after it; each returns the process exit code (0 ok, 1 failure, 2 usage error).
#include <string>
#include <vector>

namespace pslam {

// `pslam eval`: relative pose error of a trajectory, or KL divergence between two maps.
int RunEvalCommand(const std::vector<std::string>& args);

// `pslam experiment NAME`: the experiments of the paper's section V (explore, hypotheses,
// particles, latency); the first argument names the experiment.
int RunExperimentCommand(const std::vector<std::string>& args);

// `pslam run`: maps a CARMEN log with the particle filter.
int RunRunCommand(const std::vector<std::string>& args);

// `pslam localize`: Monte Carlo localization of a CARMEN log on a fixed map.
int RunLocalizeCommand(const std::vector<std::string>& args);
// `pslam worlds generate`: writes generated floor plans as map_server worlds.
int RunWorldsCommand(const std::vector<std::string>& args);

}  // namespace pslam
