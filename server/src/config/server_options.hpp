#pragma once
// Every setting of pslam-server, with its default, in one place: a JSON config file
// (schema/config/server.schema.json) overridden by command-line flags. Unknown keys and flags are
// errors that name the culprit.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/result.hpp"
#include "engine/session_engine.hpp"
#include "model/session_settings.hpp"
#include "net/server_context.hpp"
#include "service/settings_codec.hpp"
#include "storage/database.hpp"

namespace pslam::server {

struct ServerOptions {
  std::string host = "127.0.0.1";
  unsigned short port = 8080;                       // 0: any free port (printed at start)
  std::filesystem::path data_dir = "pslam-data";    // holds pslam.sqlite
  std::optional<std::string> postgres_url;          // storage on PostgreSQL instead of SQLite
  // A node of a fleet on that PostgreSQL database (docs/fleet.md); set with --node-id.
  std::optional<std::string> node_id;
  std::optional<std::string> advertise;             // HOST:PORT for agents; default: the listening address
  double lease_seconds = 5.0;
  std::optional<std::string> redis_url;             // live fan-out to and from other nodes
  std::optional<std::filesystem::path> web_dir;     // default: web/dist of the source tree, if found
  std::optional<std::filesystem::path> replay_dir;  // logs, relations and reference maps for replays
  int io_threads = 2;
  int http_workers = 2;
  bool sqlite_synchronous_full = true;
  bool resume_on_restart = true;
  std::vector<std::string> agent_tokens;
  std::vector<std::string> viewer_tokens;
  SessionSettings session_defaults;
  SettingsLimits settings_limits;
  EngineTiming timing;
  std::int64_t max_inflight_inputs = 256;
  std::size_t max_running_sessions = 16;
  NetLimits net;
};

struct ParsedCommandLine {
  ServerOptions options;
  bool help = false;
};

// Parses argv (config file first, then flags in order). 'program_dir' is where the binary lives,
// used to find the default web directory.
Result<ParsedCommandLine> ParseCommandLine(const std::vector<std::string>& args, const std::filesystem::path& program_dir);
// Tokens in the shipped config start with this; they must be replaced before listening beyond loopback.
inline constexpr const char* kPlaceholderTokenPrefix = "change-me";
// Checks that the options make a safe server: tokens, not the shipped placeholders, when listening
// beyond loopback.
std::optional<std::string> ValidateOptions(const ServerOptions& options);
bool IsLoopback(const std::string& host);
// Where the options say the data lives: PostgreSQL if a URL is given, else data_dir/pslam.sqlite.
StorageLocation StorageOf(const ServerOptions& options);

extern const char* const kUsage;

}  // namespace pslam::server
