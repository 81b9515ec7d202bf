#include "agent_options.hpp"

#include <cstdlib>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace pslam::agent {
namespace {

double ParseDouble(const std::string& key, const std::string& value) {
  std::size_t used = 0;
  double d = 0;
  try {
    d = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || value.empty()) throw std::invalid_argument(key + ": not a number: '" + value + "'");
  return d;
}

int ParseInt(const std::string& key, const std::string& value) {
  const double d = ParseDouble(key, value);
  if (d != static_cast<int>(d)) throw std::invalid_argument(key + ": not an integer: '" + value + "'");
  return static_cast<int>(d);
}

double Positive(const std::string& key, double d) {
  if (!(d > 0)) throw std::invalid_argument(key + " must be positive");
  return d;
}

void ParseSource(AgentOptions& o, const std::string& value) {
  const auto colon = value.find(':');
  const std::string kind = value.substr(0, colon);
  const std::string target = colon == std::string::npos ? "" : value.substr(colon + 1);
  if (kind == "sim") {
    o.source = SourceKind::kSim;
  } else if (kind == "log" && !target.empty()) {
    o.source = SourceKind::kLog;
  } else if (kind == "pioneer" && !target.empty()) {
    o.source = SourceKind::kPioneer;
  } else {
    throw std::invalid_argument("--source: expected sim[:WORLD.yaml], log:FILE.clf or pioneer:DEVICE, got '" + value + "'");
  }
  o.source_target = target;
}

void ParseServer(AgentOptions& o, const std::string& list) {
  // HOST:PORT, or the nodes of a fleet: HOST:PORT,HOST:PORT,... (the first is tried first).
  std::stringstream in(list);
  std::string value;
  std::vector<std::string> servers;
  while (std::getline(in, value, ',')) servers.push_back(value);
  if (servers.empty()) servers.push_back(list);
  for (std::size_t i = 1; i < servers.size(); ++i) {
    AgentOptions probe;
    ParseServer(probe, servers[i]);
    o.other_servers.push_back(servers[i]);
  }
  value = servers.front();
  const auto colon = value.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == value.size()) {
    throw std::invalid_argument("--server: expected HOST:PORT, got '" + value + "'");
  }
  o.server_host = value.substr(0, colon);
  o.server_port = value.substr(colon + 1);
  ParseInt("--server port", o.server_port);
}

Pose2D ParsePose(const std::string& key, const std::string& value) {
  std::vector<double> parts;
  std::stringstream in(value);
  std::string item;
  while (std::getline(in, item, ',')) parts.push_back(ParseDouble(key, item));
  if (parts.size() != 3) throw std::invalid_argument(key + ": expected x,y,theta");
  return {parts[0], parts[1], parts[2]};
}

}  // namespace

std::string AgentUsage() {
  return R"(usage: pslam-agent --server HOST:PORT[,HOST:PORT...] [--token T] --source SOURCE [options]

Streams odometry and laser scans to a pslam-server ingest WebSocket, through an on-disk spool that
survives link drops and restarts, and follows the exploration path the server sends.

sources:
  --source sim[:WORLD]        the simulator; WORLD is maze (default), office, irregular or a
                              map_server YAML with a "# start: x, y, theta" line
  --source log:FILE.clf       replay a CARMEN log with its original time stamps
  --source pioneer:/dev/ttyS0 --laser sick:/dev/ttyUSB0
                              a Pioneer 3-DX (P2OS/ARCOS) and a SICK LMS-200
  --rate N|max                log and sim: N times real time, or as fast as the link takes it (1)
  --max-scans N               log: stop after N scans (all)
  --sim-scan-rate HZ          sim: scans per second (10)
  --robot-baud N              pioneer: first baud rate tried (9600; others are probed)
  --laser-baud N              LMS-200 transfer rate: 9600, 19200, 38400 or 500000 (500000)
  --laser-offset X,Y,THETA    pioneer: laser pose on the robot, m and rad (0.018,0,0)

link:
  --token T                   agent token (else $PSLAM_AGENT_TOKEN)
  --robot-id ID               (pioneer-1)
  --session-name NAME
  --settings JSON             mapping settings of a new session, e.g. '{"particles": 40}'
                              (schema/ws/session_settings.schema.json; the server checks them)
  --mode map|localize|extend  map (default), localize on a site's map, or extend it: localize,
                              then map on from it into the site's next version (both need --site)
  --site ID                   the site the session belongs to (its latest map, to localize on)
  --initial-pose X,Y,THETA    localize, extend: the robot's start on the site's map, m and rad (else
                              global localization); --mode, --site and --initial-pose go into
                              the settings, over the same keys of --settings
  --scan-format binary|json   (binary)
  --spool DIR                 spool directory (pslam-agent-spool)
  --spool-max-mb MB           spool size bound (256)

driving:
  --no-drive                  never command the wheels
  --max-speed M/S             (0.2, the paper's top speed)
  --lookahead M               pure-pursuit look-ahead distance (0.5)
  --stop-distance M           clearance kept in front of the robot (0.3)
  --link-timeout S            stop the robot when the server is silent this long (1.5)

  --status-period S           status line period (10)
  --close-on-exit             close the session on the server when stopped (default for sim)
  --keep-session              leave it open, to be resumed by the next run (default otherwise)
  --verbose                   debug logging
)";
}

ParsedOptions ParseAgentOptions(const std::vector<std::string>& args) {
  ParsedOptions result;
  AgentOptions o;
  if (const char* token = std::getenv("PSLAM_AGENT_TOKEN")) o.token = token;
  bool have_server = false, have_source = false;
  nlohmann::json settings = nlohmann::json::object();
  // --mode, --site and --initial-pose: merged into the settings once all options are read.
  nlohmann::json localize = nlohmann::json::object();
  std::optional<bool> close_on_exit;
  using Setter = std::function<void(const std::string&)>;
  const std::map<std::string, Setter> with_value = {
      {"--server", [&](const std::string& v) { ParseServer(o, v); have_server = true; }},
      {"--token", [&](const std::string& v) { o.token = v; }},
      {"--source", [&](const std::string& v) { ParseSource(o, v); have_source = true; }},
      {"--laser", [&](const std::string& v) {
         if (v.rfind("sick:", 0) != 0 || v.size() <= 5) throw std::invalid_argument("--laser: expected sick:DEVICE, got '" + v + "'");
         o.laser_device = v.substr(5);
       }},
      {"--rate", [&](const std::string& v) { o.rate = v == "max" ? 0.0 : Positive("--rate", ParseDouble("--rate", v)); }},
      {"--max-scans", [&](const std::string& v) { o.max_scans = static_cast<std::size_t>(Positive("--max-scans", ParseInt("--max-scans", v))); }},
      {"--sim-scan-rate", [&](const std::string& v) { o.sim_scan_rate_hz = Positive("--sim-scan-rate", ParseDouble("--sim-scan-rate", v)); }},
      {"--robot-baud", [&](const std::string& v) { o.robot_baud = ParseInt("--robot-baud", v); }},
      {"--laser-baud", [&](const std::string& v) {
         o.laser_baud = ParseInt("--laser-baud", v);
         if (!sick::BaudMode(o.laser_baud)) throw std::invalid_argument("--laser-baud: the LMS-200 supports 9600, 19200, 38400, 500000");
       }},
      {"--laser-offset", [&](const std::string& v) { o.laser_offset = ParsePose("--laser-offset", v); }},
      {"--robot-id", [&](const std::string& v) { o.robot_id = v; }},
      {"--session-name", [&](const std::string& v) { o.session_name = v; }},
      {"--settings", [&](const std::string& v) {
         settings = nlohmann::json::parse(v, nullptr, false);
         if (!settings.is_object()) throw std::invalid_argument("--settings: a JSON object, got '" + v + "'");
       }},
      {"--mode", [&](const std::string& v) {
         if (v != "map" && v != "localize" && v != "extend") {
           throw std::invalid_argument("--mode: map, localize or extend, got '" + v + "'");
         }
         localize["mode"] = v;
       }},
      {"--site", [&](const std::string& v) {
         if (v.empty()) throw std::invalid_argument("--site: a site id, e.g. site-0123456789abcdef");
         localize["site"] = v;
       }},
      {"--initial-pose", [&](const std::string& v) {
         const Pose2D p = ParsePose("--initial-pose", v);
         localize["initial_pose"] = {{"x", p.x}, {"y", p.y}, {"theta", p.theta}};
       }},
      {"--scan-format", [&](const std::string& v) {
         if (v != "binary" && v != "json") throw std::invalid_argument("--scan-format: binary or json, got '" + v + "'");
         o.binary_scans = v == "binary";
       }},
      {"--spool", [&](const std::string& v) { o.spool_dir = v; }},
      {"--spool-max-mb", [&](const std::string& v) { o.spool_max_mb = Positive("--spool-max-mb", ParseDouble("--spool-max-mb", v)); }},
      {"--max-speed", [&](const std::string& v) { o.follower.max_linear_speed = Positive("--max-speed", ParseDouble("--max-speed", v)); }},
      {"--lookahead", [&](const std::string& v) { o.follower.lookahead_distance = Positive("--lookahead", ParseDouble("--lookahead", v)); }},
      {"--stop-distance", [&](const std::string& v) { o.safety.stop_distance_m = Positive("--stop-distance", ParseDouble("--stop-distance", v)); }},
      {"--link-timeout", [&](const std::string& v) { o.safety.link_timeout_s = Positive("--link-timeout", ParseDouble("--link-timeout", v)); }},
      {"--status-period", [&](const std::string& v) { o.status_period_s = Positive("--status-period", ParseDouble("--status-period", v)); }},
  };
  const std::map<std::string, std::function<void()>> flags = {
      {"--no-drive", [&] { o.drive = false; }},
      {"--close-on-exit", [&] { close_on_exit = true; }},
      {"--keep-session", [&] { close_on_exit = false; }},
      {"--verbose", [&] { o.verbose = true; }},
      {"--help", [&] { result.help = true; }},
      {"-h", [&] { result.help = true; }},
  };
  try {
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& key = args[i];
      if (const auto f = flags.find(key); f != flags.end()) {
        f->second();
        continue;
      }
      const auto s = with_value.find(key);
      if (s == with_value.end()) throw std::invalid_argument("unknown option '" + key + "'");
      if (i + 1 >= args.size()) throw std::invalid_argument("missing value after " + key);
      s->second(args[++i]);
    }
    if (result.help) return result;
    if (!have_server) throw std::invalid_argument("--server HOST:PORT is required");
    if (!have_source) throw std::invalid_argument("--source is required");
    if (o.source == SourceKind::kPioneer && o.laser_device.empty()) {
      throw std::invalid_argument("--source pioneer:... needs --laser sick:DEVICE");
    }
    if (o.source != SourceKind::kPioneer && !o.laser_device.empty()) {
      throw std::invalid_argument("--laser is only for --source pioneer:...");
    }
    settings.update(localize);
    if (settings.value("mode", "map") != "map" && !settings.contains("site")) {
      throw std::invalid_argument("--mode " + settings.value("mode", "map") + " needs --site ID (the site whose map to localize on)");
    }
    if (settings.contains("initial_pose") && settings.value("mode", "map") == "map") {
      throw std::invalid_argument("--initial-pose is for --mode localize or extend");
    }
    if (!settings.empty()) o.session_settings_json = settings.dump();
  } catch (const std::invalid_argument& e) {
    result.error = e.what();
    return result;
  }
  o.close_on_exit = close_on_exit.value_or(o.source == SourceKind::kSim);
  result.options = o;
  return result;
}

}  // namespace pslam::agent
