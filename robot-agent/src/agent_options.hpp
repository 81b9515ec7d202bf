#pragma once
// Every tunable of pslam-agent in one typed struct, with its defaults here and nowhere else, parsed
// from the command line. Unknown or malformed options are rejected with the offending option named.
#include <optional>
#include <string>
#include <vector>

#include "devices/p2os_client.hpp"
#include "devices/sick_client.hpp"
#include "drive/safety.hpp"
#include "drive/stall_recovery.hpp"
#include "link/server_link.hpp"
#include "link/spool.hpp"
#include "pslam/explore/path_follower.hpp"

namespace pslam::agent {

enum class SourceKind { kSim, kLog, kPioneer };

struct AgentOptions {
  // Link.
  std::string server_host;
  std::string server_port;
  std::vector<std::string> other_servers;  // further nodes of a fleet, HOST:PORT
  std::string token;  // --token, else $PSLAM_AGENT_TOKEN
  std::string robot_id = "pioneer-1";
  std::string session_name;
  std::string session_settings_json;  // a JSON object sent as hello.settings; empty: none
  bool binary_scans = true;
  // Close the session on the server when the agent stops (POST /api/sessions/{id}/close), instead
  // of leaving it to be resumed. Default: for the simulator, whose robot starts afresh each run.
  bool close_on_exit = false;

  // Source: "sim[:WORLD]", "log:FILE", "pioneer:DEVICE" (+ "--laser sick:DEVICE").
  SourceKind source = SourceKind::kSim;
  std::string source_target;  // world, log file or robot device
  std::string laser_device;
  double rate = 1.0;          // log and sim: times real time; 0 = "max"
  double sim_scan_rate_hz = 10.0;
  std::size_t max_scans = 0;  // log: stop after this many scans (0: all)
  int robot_baud = 9600;
  int laser_baud = 500000;
  Pose2D laser_offset{0.018, 0.0, 0.0};

  // Spool.
  std::string spool_dir = "pslam-agent-spool";
  double spool_max_mb = 256.0;

  // Driving.
  bool drive = true;
  FollowerOptions follower;  // core's pure pursuit (pslam/explore/path_follower.hpp)
  SafetyOptions safety;
  StallOptions stall;

  double status_period_s = 10.0;
  bool verbose = false;
};

struct ParsedOptions {
  std::optional<AgentOptions> options;  // set on success
  std::string error;                    // set on failure: names the offending option
  bool help = false;                    // --help was given
};

ParsedOptions ParseAgentOptions(const std::vector<std::string>& args);
std::string AgentUsage();

}  // namespace pslam::agent
