#include "config/server_options.hpp"

#include <nlohmann/json.hpp>

#include <charconv>
#include <fstream>

#include "net/redis_connection.hpp"
#include "service/api_error.hpp"
#include "service/json_fields.hpp"

namespace pslam::server {

const char* const kUsage =
    "usage: pslam-server [--config FILE] [--listen HOST:PORT] [--data DIR] [--web DIR] [--replay-dir DIR]\n"
    "                    [--particles N] [--seed N] [--predict on|off] [--filter-threads N]\n"
    "                    [--io-threads N] [--http-workers N] [--agent-token T]... [--viewer-token T]...\n"
    "                    [--max-inflight N] [--max-sessions N] [--max-message-bytes N] [--max-body-bytes N]\n"
    "                    [--hello-timeout S] [--max-agent-sockets N] [--max-viewer-sockets N]\n"
    "                    [--max-sockets-per-token N]\n"
    "                    [--checkpoint-seconds S] [--sqlite-sync full|normal] [--on-restart resume|close]\n"
    "                    [--postgres URL [--node-id ID [--advertise HOST:PORT] [--lease-seconds S]]]\n"
    "                    [--redis URL]\n"
    "                    [--session-memory-mb N]\n"
    "  Listens on 127.0.0.1:8080 by default; port 0 picks a free port. Beyond loopback, agent (write)\n"
    "  and viewer (read) tokens are required. Flags override the config file (JSON, see\n"
    "  schema/config/server.schema.json).\n";

namespace {

bool ParseListen(const std::string& text, ServerOptions& o) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) return false;
  std::string host = text.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  unsigned port = 0;
  const std::string p = text.substr(colon + 1);
  const auto [ptr, ec] = std::from_chars(p.data(), p.data() + p.size(), port);
  if (ec != std::errc() || ptr != p.data() + p.size() || port > 65535) return false;
  o.host = host;
  o.port = static_cast<unsigned short>(port);
  return true;
}

std::vector<std::string> Tokens(JsonFields& f, const std::string& key) {
  std::vector<std::string> out;
  if (const nlohmann::json* list = f.Array(key)) {
    for (const auto& t : *list) {
      if (!t.is_string() || t.get<std::string>().size() < 8) f.Fail(key, "must hold strings of at least 8 characters");
      out.push_back(t.get<std::string>());
    }
  }
  return out;
}

void ApplyConfigFile(const std::filesystem::path& path, ServerOptions& o) {
  std::ifstream in(path);
  if (!in) throw ApiError::BadRequest("cannot read config file " + path.string());
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) throw ApiError::BadRequest("config file " + path.string() + " is not valid JSON");
  JsonFields f(j, "config");
  if (auto v = f.String("listen")) {
    if (!ParseListen(*v, o)) f.Fail("listen", "must be HOST:PORT");
  }
  if (auto v = f.String("data_dir", 4096)) o.data_dir = *v;
  if (auto v = f.String("web_dir", 4096)) o.web_dir = std::filesystem::path(*v);
  if (auto v = f.String("replay_dir", 4096)) o.replay_dir = std::filesystem::path(*v);
  if (auto v = f.Integer("io_threads")) o.io_threads = static_cast<int>(*v);
  if (auto v = f.Integer("http_workers")) o.http_workers = static_cast<int>(*v);
  if (auto v = f.String("sqlite_synchronous")) {
    if (*v != "full" && *v != "normal") f.Fail("sqlite_synchronous", "must be full or normal");
    o.sqlite_synchronous_full = *v == "full";
  }
  if (const nlohmann::json* storage = f.Object("storage")) {
    JsonFields s(*storage, "config.storage");
    const auto kind = s.String("kind");
    const auto url = s.String("url", 4096);
    if (kind && *kind != "sqlite" && *kind != "postgres") s.Fail("kind", "must be sqlite or postgres");
    if (kind == "postgres" && !url) s.Fail("url", "is required with kind postgres");
    if (kind != "postgres" && url) s.Fail("url", "is only for kind postgres");
    o.postgres_url = kind == "postgres" ? url : std::nullopt;
    s.RejectUnknown();
  }
  if (const nlohmann::json* cluster = f.Object("cluster")) {
    JsonFields c(*cluster, "config.cluster");
    o.node_id = c.String("node_id", 64);
    if (!o.node_id) c.Fail("node_id", "is required");
    if (auto v = c.String("advertise", 256)) o.advertise = *v;
    o.lease_seconds = c.NumberOr("lease_seconds", o.lease_seconds);
    c.RejectUnknown();
  }
  if (const nlohmann::json* redis = f.Object("redis")) {
    JsonFields r(*redis, "config.redis");
    const auto url = r.String("url", 4096);
    if (!url) r.Fail("url", "is required");
    if (const auto address = ParseRedisUrl(*url); !address) r.Fail("url", address.error());
    o.redis_url = url;
    r.RejectUnknown();
  }
  if (auto v = f.String("on_restart")) {
    if (*v != "resume" && *v != "close") f.Fail("on_restart", "must be resume or close");
    o.resume_on_restart = *v == "resume";
  }
  if (const nlohmann::json* tokens = f.Object("tokens")) {
    JsonFields t(*tokens, "config.tokens");
    o.agent_tokens = Tokens(t, "agent");
    o.viewer_tokens = Tokens(t, "viewer");
    t.RejectUnknown();
  }
  if (const nlohmann::json* limits = f.Object("limits")) {
    JsonFields l(*limits, "config.limits");
    if (auto v = l.Integer("max_particles")) o.settings_limits.max_particles = static_cast<int>(*v);
    if (auto v = l.Integer("max_beams")) o.settings_limits.max_beams = static_cast<int>(*v);
    if (auto v = l.Integer("max_filter_threads")) o.settings_limits.max_threads = static_cast<int>(*v);
    if (auto v = l.Integer("max_session_memory_mb")) o.settings_limits.max_memory_mb = static_cast<int>(*v);
    if (auto v = l.Integer("max_inflight_inputs")) o.max_inflight_inputs = *v;
    if (auto v = l.Integer("max_running_sessions")) o.max_running_sessions = static_cast<std::size_t>(*v);
    if (auto v = l.Integer("max_message_bytes")) o.net.max_message_bytes = static_cast<std::size_t>(*v);
    if (auto v = l.Integer("max_body_bytes")) o.net.max_body_bytes = static_cast<std::size_t>(*v);
    if (auto v = l.Integer("max_agent_websockets")) o.net.max_agent_websockets = static_cast<std::size_t>(*v);
    if (auto v = l.Integer("max_viewer_websockets")) o.net.max_viewer_websockets = static_cast<std::size_t>(*v);
    if (auto v = l.Integer("max_websockets_per_token")) o.net.max_websockets_per_token = static_cast<std::size_t>(*v);
    if (auto v = l.Integer("hello_timeout_seconds")) o.net.hello_timeout = std::chrono::seconds(*v);
    if (auto v = l.Integer("http_timeout_seconds")) o.net.http_timeout = std::chrono::seconds(*v);
    l.RejectUnknown();
  }
  if (const nlohmann::json* timing = f.Object("timing")) {
    JsonFields t(*timing, "config.timing");
    o.timing.live_period_seconds = t.NumberOr("live_period_seconds", o.timing.live_period_seconds);
    o.timing.checkpoint_period_seconds = t.NumberOr("checkpoint_period_seconds", o.timing.checkpoint_period_seconds);
    t.RejectUnknown();
  }
  if (const nlohmann::json* s = f.Object("session_defaults")) {
    o.session_defaults = ParseSessionSettings(*s, o.session_defaults, o.settings_limits, "config.session_defaults");
  }
  f.RejectUnknown();
}

}  // namespace

bool IsLoopback(const std::string& host) {
  return host == "127.0.0.1" || host == "::1" || host == "localhost" || host.rfind("127.", 0) == 0;
}

Result<ParsedCommandLine> ParseCommandLine(const std::vector<std::string>& args, const std::filesystem::path& program_dir) {
  ParsedCommandLine parsed;
  ServerOptions& o = parsed.options;
  try {
    // The config file first, wherever --config appears, so flags always win.
    for (std::size_t i = 0; i + 1 < args.size(); ++i) {
      if (args[i] == "--config") ApplyConfigFile(args[i + 1], o);
    }
    nlohmann::json overrides = nlohmann::json::object();
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& flag = args[i];
      if (flag == "--help" || flag == "-h") {
        parsed.help = true;
        continue;
      }
      if (i + 1 >= args.size()) return Error{"flag " + flag + " needs a value (or is unknown)"};
      const std::string value = args[++i];
      auto integer = [&](long long min, long long max) {
        long long v = 0;
        const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || ptr != value.data() + value.size() || v < min || v > max) {
          throw ApiError::BadRequest(flag + " must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
        }
        return v;
      };
      if (flag == "--config") {
      } else if (flag == "--listen") {
        if (!ParseListen(value, o)) return Error{"--listen must be HOST:PORT"};
      } else if (flag == "--data") {
        o.data_dir = value;
      } else if (flag == "--postgres") {
        if (value.rfind("postgres://", 0) != 0 && value.rfind("postgresql://", 0) != 0) {
          return Error{"--postgres must be a URL postgresql://USER@HOST:PORT/DATABASE"};
        }
        o.postgres_url = value;
      } else if (flag == "--node-id") {
        if (value.empty() || value.size() > 64) return Error{"--node-id must be 1 to 64 characters"};
        o.node_id = value;
      } else if (flag == "--advertise") {
        ServerOptions probe;
        if (!ParseListen(value, probe) || probe.port == 0) return Error{"--advertise must be HOST:PORT"};
        o.advertise = value;
      } else if (flag == "--lease-seconds") {
        o.lease_seconds = static_cast<double>(integer(1, 3600));
      } else if (flag == "--redis") {
        if (const auto address = ParseRedisUrl(value); !address) return Error{"--redis " + address.error()};
        o.redis_url = value;
      } else if (flag == "--web") {
        o.web_dir = std::filesystem::path(value);
      } else if (flag == "--replay-dir") {
        o.replay_dir = std::filesystem::path(value);
      } else if (flag == "--particles") {
        overrides["particles"] = integer(1, 1000000);
      } else if (flag == "--seed") {
        overrides["seed"] = integer(0, INT64_MAX);
      } else if (flag == "--predict") {
        if (value != "on" && value != "off") return Error{"--predict must be on or off"};
        overrides["predict"] = value == "on";
      } else if (flag == "--session-memory-mb") {
        overrides["memory_limit_mb"] = integer(16, 1 << 20);
      } else if (flag == "--filter-threads") {
        overrides["threads"] = integer(1, 1024);
      } else if (flag == "--io-threads") {
        o.io_threads = static_cast<int>(integer(1, 64));
      } else if (flag == "--http-workers") {
        o.http_workers = static_cast<int>(integer(1, 64));
      } else if (flag == "--agent-token") {
        if (value.size() < 8) return Error{"--agent-token must be at least 8 characters"};
        o.agent_tokens.push_back(value);
      } else if (flag == "--viewer-token") {
        if (value.size() < 8) return Error{"--viewer-token must be at least 8 characters"};
        o.viewer_tokens.push_back(value);
      } else if (flag == "--max-inflight") {
        o.max_inflight_inputs = integer(1, 1000000);
      } else if (flag == "--max-sessions") {
        o.max_running_sessions = static_cast<std::size_t>(integer(1, 10000));
      } else if (flag == "--max-message-bytes") {
        o.net.max_message_bytes = static_cast<std::size_t>(integer(1024, 1LL << 30));
      } else if (flag == "--max-body-bytes") {
        o.net.max_body_bytes = static_cast<std::size_t>(integer(1024, 1LL << 30));
      } else if (flag == "--hello-timeout") {
        o.net.hello_timeout = std::chrono::seconds(integer(1, 3600));
      } else if (flag == "--max-agent-sockets") {
        o.net.max_agent_websockets = static_cast<std::size_t>(integer(1, 100000));
      } else if (flag == "--max-viewer-sockets") {
        o.net.max_viewer_websockets = static_cast<std::size_t>(integer(1, 100000));
      } else if (flag == "--max-sockets-per-token") {
        o.net.max_websockets_per_token = static_cast<std::size_t>(integer(1, 100000));
      } else if (flag == "--checkpoint-seconds") {
        o.timing.checkpoint_period_seconds = static_cast<double>(integer(1, 3600));
      } else if (flag == "--sqlite-sync") {
        if (value != "full" && value != "normal") return Error{"--sqlite-sync must be full or normal"};
        o.sqlite_synchronous_full = value == "full";
      } else if (flag == "--on-restart") {
        if (value != "resume" && value != "close") return Error{"--on-restart must be resume or close"};
        o.resume_on_restart = value == "resume";
      } else {
        return Error{"unknown flag " + flag};
      }
    }
    o.session_defaults = ParseSessionSettings(overrides, o.session_defaults, o.settings_limits, "flags");
  } catch (const ApiError& e) {
    return Error{e.what()};
  }
  if (!o.web_dir) {
    // build/bin/pslam-server -> <source tree>/web/dist; else ./web/dist.
    for (const auto& candidate : {program_dir / ".." / ".." / "web" / "dist", std::filesystem::path("web") / "dist"}) {
      std::error_code ec;
      if (std::filesystem::is_directory(candidate, ec)) {
        o.web_dir = candidate;
        break;
      }
    }
  }
  return parsed;
}

StorageLocation StorageOf(const ServerOptions& o) {
  if (o.postgres_url) return {StorageKind::kPostgres, *o.postgres_url};
  return {StorageKind::kSqlite, (o.data_dir / "pslam.sqlite").string(), o.sqlite_synchronous_full};
}

std::optional<std::string> ValidateOptions(const ServerOptions& o) {
  if (o.node_id && !o.postgres_url) return "--node-id makes a node of a fleet, which shares PostgreSQL: give --postgres URL";
  if (!(o.lease_seconds >= 1 && o.lease_seconds <= 3600)) return "cluster.lease_seconds must be in [1, 3600]";
  if (!IsLoopback(o.host) && o.agent_tokens.empty()) {
    return "listening on " + o.host + " (beyond loopback) needs at least one --agent-token (and --viewer-token for viewers)";
  }
  if (!IsLoopback(o.host)) {
    // The shipped config's tokens are public: anyone who read it could drive the robot.
    for (const auto* list : {&o.agent_tokens, &o.viewer_tokens}) {
      for (const std::string& token : *list) {
        if (token.rfind(kPlaceholderTokenPrefix, 0) == 0) {
          return "refusing to listen on " + o.host + " (beyond loopback) with the placeholder token '" + token +
                 "': replace every " + kPlaceholderTokenPrefix + "... token in the config with a secret of your own";
        }
      }
    }
  }
  if (o.io_threads < 1 || o.http_workers < 1) return "io_threads and http_workers must be at least 1";
  if (o.max_inflight_inputs < 1) return "max_inflight_inputs must be at least 1";
  if (o.net.hello_timeout.count() < 1 || o.net.max_agent_websockets < 1 || o.net.max_viewer_websockets < 1 ||
      o.net.max_websockets_per_token < 1) {
    return "hello_timeout_seconds and the WebSocket quotas must be at least 1";
  }
  if (o.timing.live_period_seconds < 0.01 || o.timing.checkpoint_period_seconds < 0.1) {
    return "timing periods are too short (live >= 0.01 s, checkpoint >= 0.1 s)";
  }
  return std::nullopt;
}

}  // namespace pslam::server
