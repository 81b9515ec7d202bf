#pragma once
// Plumbing for pslam-server-bench: the real pslam-server started with fork/exec on 127.0.0.1 with a
// random port, a Beast HTTP client and WebSocket connect helpers, all with time limits (nothing here
// can wait forever), and small statistics helpers. No gtest: the benchmark is a plain program.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "testing/server_launch.hpp"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace pslam::bench {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

inline double SecondsBetween(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }
inline std::int64_t NanosSince(Clock::time_point epoch) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - epoch).count();
}

// ---------------------------------------------------------------------------------------------
// The server process.

class ServerProcess {
 public:
  // Starts 'binary' with --listen 127.0.0.1:0 --data DATA_DIR and 'extra_args'; stderr goes to
  // 'log_path'. Throws if the server does not print its port within 30 s.
  ServerProcess(const std::string& binary, const std::filesystem::path& data_dir, const std::vector<std::string>& extra_args,
                const std::filesystem::path& log_path) {
    const auto server = ::pslam::testing::LaunchServer(binary, data_dir, extra_args, log_path, 30s);
    pid_ = server.pid;
    stdout_ = server.stdout_fd;
    port_ = server.port;
  }
  ~ServerProcess() {
    Stop();
    if (stdout_ >= 0) close(stdout_);
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  unsigned short port() const { return port_; }
  pid_t pid() const { return pid_; }

  // User + system CPU seconds of the server so far (all threads), from /proc.
  double CpuSeconds() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto close_paren = text.rfind(')');
    if (close_paren == std::string::npos) return 0.0;
    std::istringstream fields(text.substr(close_paren + 2));
    std::string f;
    double utime = 0, stime = 0;
    for (int i = 3; i <= 15 && fields >> f; ++i) {  // field 3 is the state; 14 utime, 15 stime
      if (i == 14) utime = std::stod(f);
      if (i == 15) stime = std::stod(f);
    }
    return (utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
  }

  // CPU seconds per thread id (user + system), from /proc/PID/task.
  std::map<int, double> ThreadCpuSeconds() const {
    std::map<int, double> out;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/" + std::to_string(pid_) + "/task", ec)) {
      std::ifstream in(entry.path() / "stat");
      std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      const auto close_paren = text.rfind(')');
      if (close_paren == std::string::npos) continue;
      std::istringstream fields(text.substr(close_paren + 2));
      std::string f;
      double cpu = 0;
      for (int i = 3; i <= 15 && fields >> f; ++i) {
        if (i == 14 || i == 15) cpu += std::stod(f);
      }
      out[std::stoi(entry.path().filename().string())] = cpu / static_cast<double>(sysconf(_SC_CLK_TCK));
    }
    return out;
  }

  // SIGTERM, then up to 60 s for the orderly shutdown, then SIGKILL. Returns the exit status.
  int Stop() {
    if (pid_ <= 0) return -1;
    kill(pid_, SIGTERM);
    int status = 0;
    const auto deadline = Clock::now() + 60s;
    for (;;) {
      const pid_t r = waitpid(pid_, &status, WNOHANG);
      if (r == pid_) break;
      if (r < 0 || Clock::now() > deadline) {
        kill(pid_, SIGKILL);
        waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(50ms);
    }
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

 private:
  pid_t pid_ = -1;
  int stdout_ = -1;
  unsigned short port_ = 0;
};

// ---------------------------------------------------------------------------------------------
// HTTP: one request per connection, every step bounded by 'timeout'.

struct HttpResult {
  int status = 0;  // 0: no response (error says why)
  std::string body;
  std::string error;
  double ms = 0.0;  // connect to last body byte
};

inline HttpResult HttpRequest(unsigned short port, http::verb method, const std::string& target, const std::string& body = "",
                              std::chrono::milliseconds timeout = 30s) {
  asio::io_context ioc;
  beast::tcp_stream stream(ioc);
  http::request<http::string_body> req{method, target, 11};
  req.set(http::field::host, "127.0.0.1");
  if (!body.empty()) {
    req.set(http::field::content_type, "application/json");
    req.body() = body;
  }
  req.prepare_payload();
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(512u << 20);
  HttpResult r;
  const auto start = Clock::now();
  stream.expires_after(timeout);  // bounds connect, write and read together
  stream.async_connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), [&](beast::error_code ec) {
    if (ec) {
      r.error = "connect: " + ec.message();
      return;
    }
    http::async_write(stream, req, [&](beast::error_code ec, std::size_t) {
      if (ec) {
        r.error = "write: " + ec.message();
        return;
      }
      http::async_read(stream, buffer, parser, [&](beast::error_code ec, std::size_t) {
        if (ec) {
          r.error = "read: " + ec.message();
          return;
        }
        r.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        r.status = static_cast<int>(parser.get().result_int());
        r.body = std::move(parser.get().body());
      });
    });
  });
  ioc.run();
  beast::error_code ignored;
  stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
  return r;
}

inline HttpResult HttpGet(unsigned short port, const std::string& target, std::chrono::milliseconds timeout = 30s) {
  return HttpRequest(port, http::verb::get, target, "", timeout);
}
inline HttpResult HttpPost(unsigned short port, const std::string& target, const std::string& body,
                           std::chrono::milliseconds timeout = 60s) {
  return HttpRequest(port, http::verb::post, target, body, timeout);
}

// ---------------------------------------------------------------------------------------------
// WebSocket helpers. A stream's io_context is run here only before its own thread runs it.

using WsStream = websocket::stream<beast::tcp_stream>;

// Runs 'ioc' until 'done' is set or 'timeout' passes; on a timeout the socket is closed, so every
// pending operation completes (with an error) before this returns.
inline bool RunUntil(asio::io_context& ioc, WsStream& ws, const bool& done, std::chrono::milliseconds timeout) {
  ioc.restart();
  const auto deadline = Clock::now() + timeout;
  while (!done && Clock::now() < deadline) {
    if (ioc.run_one_for(50ms) == 0 && ioc.stopped()) break;  // out of work without finishing
  }
  if (!done) {
    beast::error_code ignored;
    beast::get_lowest_layer(ws).socket().close(ignored);
    ioc.restart();
    ioc.run_for(2s);
  }
  ioc.restart();
  return done;
}

// TCP connect and WebSocket upgrade to 'target', within 10 s.
inline beast::error_code WsConnect(asio::io_context& ioc, WsStream& ws, unsigned short port, const std::string& target) {
  auto& lowest = beast::get_lowest_layer(ws);
  beast::error_code result = asio::error::timed_out;
  bool done = false;
  lowest.expires_after(10s);
  lowest.async_connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port), [&](beast::error_code ec) {
    if (ec) {
      result = ec;
      done = true;
      return;
    }
    ws.async_handshake("127.0.0.1", target, [&](beast::error_code ec) {
      result = ec;
      done = true;
    });
  });
  RunUntil(ioc, ws, done, 15s);
  lowest.expires_never();
  ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::client));
  ws.read_message_max(512u << 20);
  return result;
}

// Wire size of a server-to-client (unmasked) WebSocket frame carrying 'payload' bytes.
inline std::uint64_t WsWireBytes(std::uint64_t payload) { return payload + (payload < 126 ? 2 : payload < 65536 ? 4 : 10); }

// ---------------------------------------------------------------------------------------------
// Statistics.

// Nearest-rank percentile of 'v' (copied and sorted); NaN for an empty sample.
inline double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}
inline double Mean(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}
inline double Max(const std::vector<double>& v) { return v.empty() ? std::nan("") : *std::max_element(v.begin(), v.end()); }
inline double Min(const std::vector<double>& v) { return v.empty() ? std::nan("") : *std::min_element(v.begin(), v.end()); }

// CPU seconds (user + system) of this process, all threads.
inline double OwnCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

inline std::string LoadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

}  // namespace pslam::bench
