// pslam-server-bench: the service's performance targets, measured against the real pslam-server
// binary on loopback (started here with a random port and a temporary data directory).
//
//  1. Scan-to-viewer latency: the Intel log streamed into /api/ingest at its own pace (x --speed),
//     one viewer on /api/sessions/{id}/live. A scan's latency is the time from handing it to the
//     socket to the viewer receiving the first live scan frame (`PSSC`) whose seq covers it (the
//     engine's `pose` of the same tick is sent just before it). Every scan is matched; none is
//     inferred.
//  2. 50 viewers on one session: the same stream with 50 viewers (normal, slow and stalled ones);
//     the filter's rate (stats filter.scan_rate_hz and scans processed per wall second) against the
//     1-viewer run, then both again flat out (as fast as the server admits) where the filter is the
//     bottleneck and any cost of the fan-out would show.
//  3. Live bytes per second received by one viewer against resending the whole map at 10 Hz (the
//     full compressed grid, i.e. every tile frame, and the full map PNG).
//  4. GET /api/sessions/{id}/map.png latency on the streamed session (live) and on the full Intel
//     log replayed through POST /api/replays (closed, from storage): an Intel-sized map.
//
// Every wait is bounded; the program exits by itself. See server/README.md, "Server benchmark".
#include <nlohmann/json.hpp>

#include <atomic>
#include <condition_variable>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench/server_bench_support.hpp"
#include "pslam/io/carmen_reader.hpp"

#ifndef PSLAM_SERVER_BINARY
#define PSLAM_SERVER_BINARY "pslam-server"
#endif
#ifndef PSLAM_SHARED_DATA_DIR
#define PSLAM_SHARED_DATA_DIR "../shared/data"
#endif

namespace pslam::bench {
namespace {

using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Options.

struct Options {
  std::string server = PSLAM_SERVER_BINARY;
  std::string postgres;         // empty: the server's SQLite file
  std::string log = std::string(PSLAM_SHARED_DATA_DIR) + "/intel/intel.clf";
  double speed = 1.0;           // x real time; 0: as fast as the server admits
  std::size_t scans = 1500;     // scans streamed in the latency and viewers phases (~297 s of Intel log)
  int particles = 30;
  std::string predict;          // "", "on", "off": the session's predict setting (empty: server default)
  int viewers = 50;             // viewers in the fan-out phases (one of them is the measured one)
  int slow_viewers = 8;         // read one message per --slow-delay-ms
  int stalled_viewers = 2;      // read the snapshot, then nothing
  int slow_delay_ms = 500;
  std::size_t flat_out_scans = 3000;  // 0: skip the flat-out throughput phase
  int png_requests = 100;
  bool replay = true;           // replay the whole log for an Intel-sized map.png
  double replay_timeout_s = 900;
  std::set<std::string> phases = {"latency", "viewers", "throughput", "png"};
  std::string data_root;        // default: the system temp dir
  bool keep = false;
  bool json_stdout = false;
  std::string json_file;
};

const char* const kUsage = R"(usage: pslam-server-bench [options]
  --server PATH          pslam-server binary (default: the build's)
  --postgres URL         store on this PostgreSQL database instead of the data directory's SQLite file
  --log PATH             CARMEN log (default: shared/data/intel/intel.clf)
  --speed F              stream at F x the log's real rate (default 1; 0 = as fast as admitted)
  --scans N              scans per streamed run (default 1500, ~5 min of Intel log at 1x)
  --particles N          filter particles (default 30)
  --predict on|off       the sessions' P-SLAM predictor (default: the server's default, on)
  --viewers N            viewers in the fan-out runs (default 50: 1 measured, slow, stalled, rest normal)
  --slow-viewers N       of those, reading one message every --slow-delay-ms (default 8, 500 ms)
  --stalled-viewers N    of those, reading the snapshot and then nothing (default 2)
  --slow-delay-ms MS
  --flat-out-scans N     scans per flat-out throughput run, 1 vs N viewers (default 3000; 0 skips)
  --png-requests N       GET map.png N times per map (default 100)
  --no-replay            skip replaying the whole log (map.png is then timed on the streamed map only)
  --replay-timeout S     (default 900)
  --phases LIST          comma-separated subset of latency,viewers,throughput,png (default: all)
  --data-root DIR        where the temporary data directory goes (default: the system temp dir)
  --keep                 keep the data directory and the server log
  --json                 print the results as JSON on stdout (the table goes to stderr)
  --json-out FILE        also write the JSON to FILE
)";

Options ParseOptions(int argc, char** argv) {
  Options o;
  auto need = [&](int& i) -> std::string {
    if (i + 1 >= argc) throw std::runtime_error(std::string(argv[i]) + " needs a value");
    return argv[++i];
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else if (a == "--server") {
      o.server = need(i);
    } else if (a == "--postgres") {
      o.postgres = need(i);
    } else if (a == "--log") {
      o.log = need(i);
    } else if (a == "--speed") {
      o.speed = std::stod(need(i));
    } else if (a == "--scans") {
      o.scans = std::stoul(need(i));
    } else if (a == "--particles") {
      o.particles = std::stoi(need(i));
    } else if (a == "--predict") {
      o.predict = need(i);
      if (o.predict != "on" && o.predict != "off") throw std::runtime_error("--predict takes on or off");
    } else if (a == "--viewers") {
      o.viewers = std::stoi(need(i));
    } else if (a == "--slow-viewers") {
      o.slow_viewers = std::stoi(need(i));
    } else if (a == "--stalled-viewers") {
      o.stalled_viewers = std::stoi(need(i));
    } else if (a == "--slow-delay-ms") {
      o.slow_delay_ms = std::stoi(need(i));
    } else if (a == "--flat-out-scans") {
      o.flat_out_scans = std::stoul(need(i));
    } else if (a == "--png-requests") {
      o.png_requests = std::stoi(need(i));
    } else if (a == "--no-replay") {
      o.replay = false;
    } else if (a == "--replay-timeout") {
      o.replay_timeout_s = std::stod(need(i));
    } else if (a == "--phases") {
      o.phases.clear();
      std::stringstream list(need(i));
      std::string p;
      while (std::getline(list, p, ',')) {
        if (p != "latency" && p != "viewers" && p != "throughput" && p != "png") throw std::runtime_error("unknown phase " + p);
        o.phases.insert(p);
      }
    } else if (a == "--data-root") {
      o.data_root = need(i);
    } else if (a == "--keep") {
      o.keep = true;
    } else if (a == "--json") {
      o.json_stdout = true;
    } else if (a == "--json-out") {
      o.json_file = need(i);
    } else {
      throw std::runtime_error("unknown option " + a + " (see --help)");
    }
  }
  if (o.speed < 0 || o.scans < 2 || o.particles < 1 || o.viewers < 1 || o.png_requests < 1 || o.slow_delay_ms < 0 ||
      o.slow_viewers < 0 || o.stalled_viewers < 0 || o.slow_viewers + o.stalled_viewers > o.viewers - 1) {
    throw std::runtime_error("bad option values (see --help)");
  }
  return o;
}

// ---------------------------------------------------------------------------------------------
// The log.

struct BenchScan {
  double t = 0, x = 0, y = 0, theta = 0;
  std::vector<float> ranges;
};

struct LogData {
  json laser;
  std::vector<BenchScan> scans;
};

LogData LoadScans(const std::string& path, std::size_t max_scans) {
  CarmenReader reader(path);
  ScanStream stream(reader);
  LogData d;
  std::size_t beams = 0;
  while (d.scans.size() < max_scans) {
    std::optional<LaserScan> s = stream.Next();
    if (!s) break;
    if (d.scans.empty()) {
      beams = s->ranges.size();
      d.laser = {{"angle_min", s->angle_min},
                 {"angle_increment", s->angle_increment},
                 {"beams", beams},
                 {"max_range", s->max_range},
                 {"min_range", s->min_range},
                 {"offset", {{"x", s->sensor_offset.x}, {"y", s->sensor_offset.y}, {"theta", s->sensor_offset.theta}}}};
    }
    if (s->ranges.size() != beams) continue;  // another laser: not this session's
    d.scans.push_back({s->timestamp, s->odometry.x, s->odometry.y, s->odometry.theta, std::move(s->ranges)});
  }
  return d;
}

// A PSC1 binary scan (schema/ws/ingest.md), little-endian.
std::string EncodeScan(std::int64_t seq, const BenchScan& s) {
  std::string out(48 + 4 * s.ranges.size(), '\0');
  auto put = [&](std::size_t at, const auto& v) { std::memcpy(out.data() + at, &v, sizeof v); };
  std::memcpy(out.data(), "PSC1", 4);
  put(4, static_cast<std::uint64_t>(seq));
  put(12, s.t);
  put(20, s.x);
  put(28, s.y);
  put(36, s.theta);
  put(44, static_cast<std::uint32_t>(s.ranges.size()));
  std::memcpy(out.data() + 48, s.ranges.data(), 4 * s.ranges.size());
  return out;
}

// ---------------------------------------------------------------------------------------------
// Per-scan times: sent (agent thread), acked (agent thread), first seen processed by the measured
// viewer (its thread). Nanoseconds since the run's epoch; 0 = not yet.

class Recorder {
 public:
  explicit Recorder(std::size_t n)
      : n_(n), sent_(new std::atomic<std::int64_t>[n + 1]), acked_(new std::atomic<std::int64_t>[n + 1]),
        viewed_(new std::atomic<std::int64_t>[n + 1]) {
    for (std::size_t i = 0; i <= n; ++i) sent_[i] = acked_[i] = viewed_[i] = 0;
  }
  void Sent(std::int64_t seq, std::int64_t ns) { sent_[seq] = ns; }
  void Acked(std::int64_t upto, std::int64_t ns) {
    upto = std::min<std::int64_t>(upto, static_cast<std::int64_t>(n_));
    for (std::int64_t s = acked_upto_ + 1; s <= upto; ++s) acked_[s] = ns;
    acked_upto_ = std::max(acked_upto_.load(), upto);
  }
  void Viewed(std::int64_t upto, std::int64_t ns) {
    upto = std::min<std::int64_t>(upto, static_cast<std::int64_t>(n_));
    for (std::int64_t s = viewed_upto_ + 1; s <= upto; ++s) viewed_[s] = ns;
    viewed_upto_ = std::max(viewed_upto_.load(), upto);
  }
  std::int64_t acked_upto() const { return acked_upto_; }
  std::int64_t viewed_upto() const { return viewed_upto_; }
  double LastLatencyMs() const {
    const std::int64_t s = viewed_upto_;
    return s > 0 ? static_cast<double>(viewed_[s] - sent_[s]) / 1e6 : std::nan("");
  }
  std::int64_t SentAt(std::int64_t s) const { return sent_[s]; }
  std::int64_t AckedAt(std::int64_t s) const { return acked_[s]; }
  std::int64_t ViewedAt(std::int64_t s) const { return viewed_[s]; }
  std::vector<double> ViewLatenciesMs() const { return Diffs(viewed_.get()); }
  std::vector<double> AckLatenciesMs() const { return Diffs(acked_.get()); }

 private:
  std::vector<double> Diffs(const std::atomic<std::int64_t>* to) const {
    std::vector<double> out;
    for (std::size_t s = 1; s <= n_; ++s) {
      if (sent_[s] > 0 && to[s] > 0) out.push_back(static_cast<double>(to[s] - sent_[s]) / 1e6);
    }
    return out;
  }
  std::size_t n_;
  std::unique_ptr<std::atomic<std::int64_t>[]> sent_, acked_, viewed_;
  std::atomic<std::int64_t> acked_upto_{0}, viewed_upto_{0};
};

// ---------------------------------------------------------------------------------------------
// The agent: hello, then the scans at their log times (or flat out), acks read concurrently.

class Agent {
 public:
  Agent(const std::vector<BenchScan>& scans, std::size_t count, double speed, Recorder& rec, Clock::time_point epoch)
      : scans_(scans), count_(count), speed_(speed), rec_(rec), epoch_(epoch), ws_(ioc_), timer_(ioc_) {}
  ~Agent() { Join(); }

  // Connects, says hello and waits for the welcome; returns the session id (throws on failure).
  std::string Open(unsigned short port, const json& hello) {
    if (const auto ec = WsConnect(ioc_, ws_, port, "/api/ingest")) throw std::runtime_error("ingest connect: " + ec.message());
    bool done = false;
    beast::error_code result;
    const std::string text = hello.dump();
    ws_.text(true);
    ws_.async_write(asio::buffer(text), [&](beast::error_code ec, std::size_t) {
      result = ec;
      done = true;
    });
    if (!RunUntil(ioc_, ws_, done, 10s) || result) throw std::runtime_error("ingest hello: " + result.message());
    const auto deadline = Clock::now() + 15s;
    while (Clock::now() < deadline) {
      done = false;
      rbuf_.clear();
      ws_.async_read(rbuf_, [&](beast::error_code ec, std::size_t) {
        result = ec;
        done = true;
      });
      if (!RunUntil(ioc_, ws_, done, 15s) || result) throw std::runtime_error("ingest welcome: " + result.message());
      const json j = json::parse(beast::buffers_to_string(rbuf_.data()), nullptr, false);
      if (j.value("type", "") == "welcome") return j.at("session_id").get<std::string>();
      if (j.value("type", "") == "error") throw std::runtime_error("ingest refused the hello: " + j.dump());
    }
    throw std::runtime_error("no welcome within 15 s");
  }

  void Start() {
    start_ = Clock::now();
    asio::post(ioc_, [this] {
      ReadAcks();
      ScheduleNext();
    });
    thread_ = std::thread([this] {
      ioc_.run();
      finished_ = true;
    });
  }

  void Close() {
    asio::post(ioc_, [this] {
      if (closing_) return;
      closing_ = true;
      timer_.cancel();
      ws_.async_close(websocket::close_code::normal, [](beast::error_code) {});
    });
  }
  bool finished() const { return finished_; }
  void Stop() { ioc_.stop(); }
  void Join() {
    if (thread_.joinable()) thread_.join();
  }

  static constexpr std::int64_t kMaxAhead = 128;
  std::int64_t sent() const { return sent_; }
  std::int64_t window_waits() const { return window_waits_; }
  bool done_sending() const { return done_sending_; }
  bool failed() const { return failed_; }
  int errors() const { return errors_; }
  int overloaded() const { return overloaded_; }
  std::string last_error() const {
    std::lock_guard lock(mutex_);
    return last_error_;
  }

 private:
  void ReadAcks() {
    ws_.async_read(rbuf_, [this](beast::error_code ec, std::size_t) {
      if (ec) {
        if (!closing_) {
          const auto reason = ws_.reason();
          Fail("ingest read: " + ec.message() + (reason.code != websocket::close_code::none
                                                      ? " (close " + std::to_string(reason.code) + " " + std::string(reason.reason.data(), reason.reason.size()) + ")"
                                                      : std::string()));
        }
        return;
      }
      const auto now = NanosSince(epoch_);
      const json j = json::parse(beast::buffers_to_string(rbuf_.data()), nullptr, false);
      rbuf_.consume(rbuf_.size());
      const std::string type = j.is_object() ? j.value("type", "") : "";
      if (type == "ack") {
        rec_.Acked(j.value("seq", std::int64_t{0}), now);
      } else if (type == "error") {
        ++errors_;
        if (j.value("code", "") == "overloaded") ++overloaded_;
        std::lock_guard lock(mutex_);
        last_error_ = j.dump();
      }
      ReadAcks();
    });
  }

  void ScheduleNext() {
    if (closing_) return;
    if (next_ >= count_) {
      done_sending_ = true;
      return;
    }
    // Stay below the server's --max-inflight (256): at most kMaxAhead scans beyond what the viewer
    // has seen processed. (When the server pauses an agent for back-pressure it drops the
    // connection instead, see server/README.md, "Server benchmark".)
    if (static_cast<std::int64_t>(next_) - rec_.viewed_upto() >= kMaxAhead) {
      ++window_waits_;
      timer_.expires_after(2ms);
      timer_.async_wait([this](beast::error_code ec) {
        if (!ec) ScheduleNext();
      });
      return;
    }
    if (speed_ <= 0) return SendNext();
    const double offset = (scans_[next_].t - scans_[0].t) / speed_;
    timer_.expires_at(start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(offset)));
    timer_.async_wait([this](beast::error_code ec) {
      if (!ec) SendNext();
    });
  }

  void SendNext() {
    const auto seq = static_cast<std::int64_t>(next_ + 1);
    wbuf_ = EncodeScan(seq, scans_[next_]);
    ++next_;
    rec_.Sent(seq, NanosSince(epoch_));
    ws_.binary(true);
    ws_.async_write(asio::buffer(wbuf_), [this, seq](beast::error_code ec, std::size_t) {
      if (ec) {
        if (!closing_) Fail("ingest write: " + ec.message());
        return;
      }
      sent_ = seq;
      ScheduleNext();
    });
  }

  void Fail(const std::string& what) {
    failed_ = true;
    std::lock_guard lock(mutex_);
    last_error_ += (last_error_.empty() ? "" : "; ") + what;
  }

  const std::vector<BenchScan>& scans_;
  const std::size_t count_;
  const double speed_;
  Recorder& rec_;
  const Clock::time_point epoch_;
  asio::io_context ioc_;
  WsStream ws_;
  asio::steady_timer timer_;
  beast::flat_buffer rbuf_;
  std::string wbuf_;
  std::size_t next_ = 0;
  Clock::time_point start_;
  bool closing_ = false;
  std::thread thread_;
  std::atomic<std::int64_t> sent_{0}, window_waits_{0};
  std::atomic<bool> done_sending_{false}, failed_{false}, finished_{false};
  std::atomic<int> errors_{0}, overloaded_{0};
  mutable std::mutex mutex_;
  std::string last_error_;
};

// ---------------------------------------------------------------------------------------------
// A viewer. All viewers count messages and bytes; the measured one also parses every message,
// reports processed_seq to the Recorder and keeps the size of every tile it holds (the full
// compressed grid).

enum class ViewerMode { kNormal, kSlow, kStalled };
const char* ModeName(ViewerMode m) {
  return m == ViewerMode::kNormal ? "normal" : m == ViewerMode::kSlow ? "slow" : "stalled";
}

struct UpdateSample {     // at every live scan frame (one per tick with a new scan) the measured viewer receives
  std::int64_t ns = 0;
  std::uint64_t delta_bytes = 0;  // cumulative, after the snapshot
  std::uint64_t grid_bytes = 0;   // sum of the latest frame of every tile held
  std::int64_t processed = 0;
};

class Viewer {
 public:
  Viewer(asio::io_context& ioc, ViewerMode mode, std::chrono::milliseconds delay, Recorder* rec, Clock::time_point epoch)
      : ioc_(ioc), ws_(ioc), timer_(ioc), mode_(mode), delay_(delay), rec_(rec), epoch_(epoch) {}

  bool Connect(unsigned short port, const std::string& session_id) {
    const auto ec = WsConnect(ioc_, ws_, port, "/api/sessions/" + session_id + "/live");
    if (ec) error_ = "connect: " + ec.message();
    connected_ = !ec;
    return connected_;
  }
  void Start() {
    if (connected_) asio::post(ioc_, [this] { Read(); });
  }
  void Close() {
    if (!connected_) return;
    asio::post(ioc_, [this] {
      if (closing_) return;
      closing_ = true;
      timer_.cancel();
      ws_.async_close(websocket::close_code::normal, [](beast::error_code) {});
    });
  }

  ViewerMode mode() const { return mode_; }
  bool connected() const { return connected_; }
  bool measured() const { return rec_ != nullptr; }
  bool got_snapshot() const { return got_snapshot_; }
  bool ended() const { return ended_; }
  std::uint64_t messages() const { return messages_; }
  std::uint64_t bytes() const { return bytes_; }
  std::uint64_t delta_bytes() const { return delta_bytes_; }
  std::uint64_t snapshot_bytes() const { return snapshot_bytes_; }
  std::uint64_t updates() const { return updates_; }
  const std::string& error() const { return error_; }
  // Measured viewer only, after its thread stopped.
  const std::vector<UpdateSample>& series() const { return series_; }
  const std::map<std::string, std::uint64_t>& bytes_by_type() const { return bytes_by_type_; }
  const std::map<std::string, std::uint64_t>& count_by_type() const { return count_by_type_; }
  std::uint64_t grid_bytes() const { return grid_bytes_; }
  std::size_t grid_tiles() const { return tile_sizes_.size(); }

 private:
  void Read() {
    if (closing_) return;
    ws_.async_read(buffer_, [this](beast::error_code ec, std::size_t) { OnRead(ec); });
  }

  void OnRead(beast::error_code ec) {
    if (ec) {
      ended_ = true;
      if (!closing_) error_ = "read: " + ec.message();
      return;
    }
    Handle(ws_.got_binary(), NanosSince(epoch_));
    buffer_.consume(buffer_.size());
    if (mode_ == ViewerMode::kStalled && got_snapshot_ && snapshot_tiles_left_ == 0) return;  // reads nothing more
    if (mode_ == ViewerMode::kSlow && got_snapshot_ && snapshot_tiles_left_ == 0) {
      timer_.expires_after(delay_);
      timer_.async_wait([this](beast::error_code ec) {
        if (!ec) Read();
      });
      return;
    }
    Read();
  }

  void Handle(bool binary, std::int64_t now) {
    const auto payload = static_cast<std::uint64_t>(buffer_.size());
    const std::uint64_t wire = WsWireBytes(payload);
    const std::string_view data(static_cast<const char*>(buffer_.cdata().data()), buffer_.size());
    ++messages_;
    bytes_ += wire;
    if (!got_snapshot_) {  // the first message is the snapshot (or an error)
      snapshot_bytes_ += wire;
      if (!binary) {
        const json j = json::parse(data, nullptr, false);
        if (j.is_object() && j.value("type", "") == "snapshot") {
          got_snapshot_ = true;
          snapshot_tiles_left_ = j.value("tile_count", 0);
        } else {
          error_ = "first message is not a snapshot: " + std::string(data.substr(0, 200));
        }
      }
      return;
    }
    if (binary && snapshot_tiles_left_ > 0) {
      --snapshot_tiles_left_;
      snapshot_bytes_ += wire;
      if (rec_) TrackTile(data, wire);
      return;
    }
    delta_bytes_ += wire;
    const std::string_view magic = binary ? data.substr(0, 4) : std::string_view();
    if (magic == "PSSC") ++updates_;
    if (!rec_) return;
    // The measured viewer.
    if (binary) {
      const std::string type = magic == "PSTL" ? "tile" : magic == "PSSC" ? "scan" : magic == "PSPT" ? "particles" : "binary?";
      bytes_by_type_[type] += wire;
      ++count_by_type_[type];
      if (magic == "PSTL") TrackTile(data, wire);
      if (magic == "PSSC" && data.size() >= 16) {
        std::int64_t seq = 0;
        std::memcpy(&seq, data.data() + 8, 8);
        rec_->Viewed(seq, now);
        series_.push_back({now, delta_bytes_, grid_bytes_, seq});
      }
      return;
    }
    const json j = json::parse(data, nullptr, false);
    const std::string type = j.is_object() ? j.value("type", "?") : "?";
    bytes_by_type_[type] += wire;
    ++count_by_type_[type];
  }

  void TrackTile(std::string_view data, std::uint64_t wire) {
    if (data.size() < 24 || data.substr(0, 4) != "PSTL") return;
    std::int32_t tx, ty;
    std::memcpy(&tx, data.data() + 4, 4);
    std::memcpy(&ty, data.data() + 8, 4);
    std::uint64_t& size = tile_sizes_[{tx, ty}];
    grid_bytes_ = grid_bytes_ - size + wire;
    size = wire;
  }

  asio::io_context& ioc_;
  WsStream ws_;
  asio::steady_timer timer_;
  const ViewerMode mode_;
  const std::chrono::milliseconds delay_;
  Recorder* const rec_;
  const Clock::time_point epoch_;
  beast::flat_buffer buffer_;
  bool connected_ = false;
  bool closing_ = false;
  int snapshot_tiles_left_ = 0;
  std::string error_;
  std::atomic<bool> got_snapshot_{false}, ended_{false};
  std::atomic<std::uint64_t> messages_{0}, bytes_{0}, delta_bytes_{0}, snapshot_bytes_{0}, updates_{0};
  std::vector<UpdateSample> series_;
  std::map<std::string, std::uint64_t> bytes_by_type_, count_by_type_;
  std::map<std::pair<int, int>, std::uint64_t> tile_sizes_;
  std::uint64_t grid_bytes_ = 0;
};

// ---------------------------------------------------------------------------------------------
// GET /api/sessions/{id}/stats once a second while a run streams.

struct StatsSample {
  double t = 0;  // seconds since the run's first scan was sent
  double rate_hz = 0, step_ms = 0, latency_ms = 0, latency_max_ms = 0, prediction_max_ms = 0, commit_ms = 0, max_commit_ms = 0;
  std::int64_t processed = 0, queued = 0, scans = 0;
};

class StatsPoller {
 public:
  StatsPoller(unsigned short port, std::string id) : port_(port), id_(std::move(id)) {}
  ~StatsPoller() { Stop(); }
  void Start(Clock::time_point t0) {
    t0_ = t0;
    thread_ = std::thread([this] { Loop(); });
  }
  void Stop() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  std::vector<StatsSample> samples() const {
    std::lock_guard lock(mutex_);
    return samples_;
  }

 private:
  void Loop() {
    for (int i = 0; i < 100000; ++i) {  // ~28 h at 1 Hz: a bound, never reached
      {
        std::unique_lock lock(mutex_);
        if (wake_.wait_for(lock, 1s, [this] { return stop_; })) return;
      }
      const HttpResult r = HttpGet(port_, "/api/sessions/" + id_ + "/stats", 5s);
      if (r.status != 200) continue;
      const json j = json::parse(r.body, nullptr, false);
      if (!j.is_object() || !j.contains("filter") || !j["filter"].is_object()) continue;
      const json& f = j["filter"];
      StatsSample s;
      s.t = SecondsBetween(t0_, Clock::now());
      s.rate_hz = f.value("scan_rate_hz", 0.0);
      s.step_ms = f.value("step_ms_mean", 0.0);
      s.latency_ms = f.value("latency_ms_mean", 0.0);
      s.latency_max_ms = f.value("latency_ms_max", 0.0);
      s.prediction_max_ms = f.value("prediction_ms_max", 0.0);
      s.processed = f.value("processed_seq", std::int64_t{0});
      s.scans = f.value("scans", std::int64_t{0});
      s.queued = f.value("queued", std::int64_t{0});
      if (j.contains("storage")) {
        s.commit_ms = j["storage"].value("last_commit_ms", 0.0);
        s.max_commit_ms = j["storage"].value("max_commit_ms", 0.0);
      }
      std::lock_guard lock(mutex_);
      samples_.push_back(s);
    }
  }
  const unsigned short port_;
  const std::string id_;
  Clock::time_point t0_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::vector<StatsSample> samples_;
  std::thread thread_;
};

// ---------------------------------------------------------------------------------------------
// One streamed run: an agent, a measured viewer and optionally more viewers.

struct ViewerResult {
  std::string mode;
  bool measured = false, connected = false, got_snapshot = false, ended = false;
  std::uint64_t messages = 0, bytes = 0, delta_bytes = 0, updates = 0;
  std::string error;
};

struct ThreadCpu {
  int tid = 0;
  double cpu_s = 0;
  bool new_in_run = false;  // started during the run: the session's engine thread
};

struct StreamResult {
  std::string label, session_id;
  std::size_t scans = 0;
  double speed = 0;
  double input_rate_hz = 0;   // the log's scan rate x speed (flat out: NaN)
  double wall_s = 0;          // first send to the viewer seeing the last scan processed (or the end)
  bool complete = false;      // every scan seen processed by the measured viewer
  std::int64_t viewed = 0;
  std::vector<double> latency_ms, ack_ms;
  double processed_per_s = 0;
  std::vector<StatsSample> stats;
  std::vector<ViewerResult> viewers;
  std::vector<UpdateSample> series;
  std::map<std::string, std::uint64_t> bytes_by_type, count_by_type;
  std::uint64_t grid_bytes_end = 0;
  std::size_t grid_tiles_end = 0;
  double grid_bytes_mean = 0;   // time-weighted over the run
  double delta_bytes_per_s = 0; // measured viewer, after its snapshot
  double updates_per_s = 0;     // measured viewer's live ticks per second
  double server_cpu_s = 0, bench_cpu_s = 0;
  std::vector<ThreadCpu> threads;  // server threads by CPU used during the run, most first
  // Per scan (index seq-1), ms since the first scan was sent; NaN where it did not happen.
  std::vector<double> sent_ms, acked_ms, viewed_ms, tick_ms;
  // Latency split by whether the scan came more or less than 100 ms after the previous tick (see
  // RunStream).
  std::vector<double> latency_after_idle_ms, latency_within_tick_ms;
  std::int64_t sent = 0, acked = 0, window_waits = 0;
  int agent_errors = 0, overloaded = 0;
  std::string agent_error;
};

struct RunSpec {
  std::string label;
  std::size_t count = 0;
  double speed = 1.0;
  int normal = 0, slow = 0, stalled = 0;  // besides the measured viewer
  std::chrono::milliseconds slow_delay{500};
};

json HelloFor(const Options& o, const json& laser, const std::string& name) {
  json settings = {{"particles", o.particles}};
  if (!o.predict.empty()) settings["predict"] = o.predict == "on";
  return {{"type", "hello"}, {"version", 1}, {"robot_id", "bench-bot"}, {"session", "new"},
          {"session_name", name}, {"laser", laser}, {"settings", settings}};
}

StreamResult RunStream(const Options& o, ServerProcess& server, const LogData& log, const RunSpec& spec) {
  const unsigned short port = server.port();
  const Clock::time_point epoch = Clock::now();
  StreamResult res;
  res.label = spec.label;
  res.scans = spec.count;
  res.speed = spec.speed;
  const double log_span = log.scans[spec.count - 1].t - log.scans[0].t;
  res.input_rate_hz = spec.speed > 0 && log_span > 0 ? static_cast<double>(spec.count - 1) / (log_span / spec.speed) : std::nan("");

  Recorder rec(spec.count);
  Agent agent(log.scans, spec.count, spec.speed, rec, epoch);
  const auto threads0 = server.ThreadCpuSeconds();  // before the hello starts the session's engine thread
  res.session_id = agent.Open(port, HelloFor(o, log.laser, "bench " + spec.label));

  // The measured viewer gets an io_context and a thread of its own, so its timestamps do not wait
  // for the other viewers' handlers.
  asio::io_context measured_ioc, others_ioc;
  std::vector<std::unique_ptr<Viewer>> viewers;
  viewers.push_back(std::make_unique<Viewer>(measured_ioc, ViewerMode::kNormal, 0ms, &rec, epoch));
  for (int i = 0; i < spec.normal; ++i) viewers.push_back(std::make_unique<Viewer>(others_ioc, ViewerMode::kNormal, 0ms, nullptr, epoch));
  for (int i = 0; i < spec.slow; ++i) viewers.push_back(std::make_unique<Viewer>(others_ioc, ViewerMode::kSlow, spec.slow_delay, nullptr, epoch));
  for (int i = 0; i < spec.stalled; ++i) viewers.push_back(std::make_unique<Viewer>(others_ioc, ViewerMode::kStalled, 0ms, nullptr, epoch));
  int failed_connects = 0;
  for (auto& v : viewers) failed_connects += v->Connect(port, res.session_id) ? 0 : 1;
  if (!viewers[0]->connected()) throw std::runtime_error("the measured viewer could not connect: " + viewers[0]->error());
  if (failed_connects) std::cerr << "[" << spec.label << "] " << failed_connects << " viewer(s) could not connect\n";
  for (auto& v : viewers) v->Start();
  std::atomic<bool> measured_done{false}, others_done{false};
  std::thread measured_thread([&] {
    measured_ioc.run();
    measured_done = true;
  });
  std::thread others_thread([&] {
    others_ioc.run();
    others_done = true;
  });
  {  // every viewer has its snapshot before the first scan
    const auto deadline = Clock::now() + 30s;
    auto all = [&] {
      for (auto& v : viewers) {
        if (v->connected() && !v->got_snapshot() && !v->ended()) return false;
      }
      return true;
    };
    while (!all() && Clock::now() < deadline) std::this_thread::sleep_for(20ms);
  }

  StatsPoller poller(port, res.session_id);
  const double own0 = OwnCpuSeconds();
  const double cpu0 = server.CpuSeconds();
  const Clock::time_point t0 = Clock::now();
  poller.Start(t0);
  agent.Start();
  const double expected_s = spec.speed > 0 ? log_span / spec.speed : static_cast<double>(spec.count) * 0.05;
  const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(expected_s * 1.5 + 120.0));
  std::optional<Clock::time_point> sent_all;
  auto last_progress = t0;
  std::cerr << "[" << spec.label << "] session " << res.session_id << ": " << spec.count << " scans, "
            << (spec.speed > 0 ? std::to_string(spec.speed) + "x real time (~" + std::to_string(static_cast<int>(expected_s)) + " s)"
                               : std::string("flat out"))
            << ", " << viewers.size() << " viewer(s)\n";
  for (;;) {
    std::this_thread::sleep_for(100ms);
    const auto now = Clock::now();
    if (rec.viewed_upto() >= static_cast<std::int64_t>(spec.count)) break;
    if (agent.failed() || now > deadline) break;
    if (agent.done_sending() && !sent_all) sent_all = now;
    if (sent_all && now - *sent_all > 120s) break;  // the filter should drain long before this
    if (now - last_progress >= 10s) {
      last_progress = now;
      std::cerr << "[" << spec.label << "] " << std::fixed << std::setprecision(0) << SecondsBetween(t0, now) << " s: sent "
                << agent.sent() << "/" << spec.count << ", acked " << rec.acked_upto() << ", processed (viewer) "
                << rec.viewed_upto() << ", last latency " << std::setprecision(1) << rec.LastLatencyMs() << " ms\n";
    }
  }
  const std::int64_t end_ns = NanosSince(epoch);
  res.server_cpu_s = server.CpuSeconds() - cpu0;
  res.bench_cpu_s = OwnCpuSeconds() - own0;
  for (const auto& [tid, cpu] : server.ThreadCpuSeconds()) {
    const auto before = threads0.find(tid);
    // CPU used since just before the hello (the engine thread: since its start).
    const double base = before == threads0.end() ? 0.0 : before->second;
    res.threads.push_back({tid, cpu - base, before == threads0.end()});
  }
  std::sort(res.threads.begin(), res.threads.end(), [](const ThreadCpu& x, const ThreadCpu& y) { return x.cpu_s > y.cpu_s; });
  poller.Stop();
  res.stats = poller.samples();
  res.complete = rec.viewed_upto() >= static_cast<std::int64_t>(spec.count);
  res.viewed = rec.viewed_upto();
  const std::int64_t first_sent = rec.SentAt(1);
  const std::int64_t last_ns = res.complete ? rec.ViewedAt(static_cast<std::int64_t>(spec.count)) : end_ns;
  res.wall_s = static_cast<double>(last_ns - first_sent) / 1e9;
  res.processed_per_s = res.wall_s > 0 ? static_cast<double>(res.viewed) / res.wall_s : 0.0;
  res.latency_ms = rec.ViewLatenciesMs();
  res.ack_ms = rec.AckLatenciesMs();
  res.sent = agent.sent();
  res.window_waits = agent.window_waits();
  res.acked = rec.acked_upto();
  res.agent_errors = agent.errors();
  res.overloaded = agent.overloaded();
  if (agent.failed()) res.agent_error = agent.last_error();
  std::vector<std::uint64_t> delta_at_end;
  for (auto& v : viewers) delta_at_end.push_back(v->delta_bytes());
  std::vector<std::uint64_t> messages_at_end, bytes_at_end, updates_at_end;
  std::vector<bool> ended_at_end;
  for (auto& v : viewers) {
    ended_at_end.push_back(v->ended());
    messages_at_end.push_back(v->messages());
    bytes_at_end.push_back(v->bytes());
    updates_at_end.push_back(v->updates());
  }

  // Close everything; whatever has not closed within 5 s is stopped.
  agent.Close();
  for (auto& v : viewers) v->Close();
  const auto close_deadline = Clock::now() + 5s;
  while ((!agent.finished() || !measured_done || !others_done) && Clock::now() < close_deadline) std::this_thread::sleep_for(20ms);
  agent.Stop();
  measured_ioc.stop();
  others_ioc.stop();
  agent.Join();
  measured_thread.join();
  others_thread.join();

  for (std::size_t i = 0; i < viewers.size(); ++i) {
    const Viewer& v = *viewers[i];
    res.viewers.push_back({ModeName(v.mode()), v.measured(), v.connected(), v.got_snapshot(), ended_at_end[i], messages_at_end[i],
                           bytes_at_end[i], delta_at_end[i], updates_at_end[i], v.error()});
  }
  const Viewer& m = *viewers[0];
  res.series = m.series();
  res.bytes_by_type = m.bytes_by_type();
  res.count_by_type = m.count_by_type();
  res.grid_bytes_end = m.grid_bytes();
  res.grid_tiles_end = m.grid_tiles();
  auto ms_since_first = [&](std::int64_t ns) { return ns > 0 ? std::round(static_cast<double>(ns - first_sent) / 1e4) / 100.0 : std::nan(""); };
  for (std::int64_t s = 1; s <= static_cast<std::int64_t>(spec.count); ++s) {
    res.sent_ms.push_back(ms_since_first(rec.SentAt(s)));
    res.acked_ms.push_back(ms_since_first(rec.AckedAt(s)));
    res.viewed_ms.push_back(ms_since_first(rec.ViewedAt(s)));
  }
  for (const UpdateSample& u : res.series) res.tick_ms.push_back(ms_since_first(u.ns));
  // Scans sent less than 100 ms after a tick (the tick before the one that carried them came later
  // than 100 ms before the scan was sent; it may even have been triggered by an earlier scan sent
  // just before): the ones a fixed 100 ms tick spacing would hold until the next tick.
  for (std::int64_t s = 1; s <= static_cast<std::int64_t>(spec.count); ++s) {
    const std::int64_t sent = rec.SentAt(s), viewed = rec.ViewedAt(s);
    if (sent == 0 || viewed == 0) continue;
    const auto carrying = std::lower_bound(res.series.begin(), res.series.end(), viewed,
                                           [](const UpdateSample& u, std::int64_t ns) { return u.ns < ns; });
    const bool held = carrying != res.series.begin() && std::prev(carrying)->ns > sent - 100'000'000;
    (held ? res.latency_within_tick_ms : res.latency_after_idle_ms).push_back(static_cast<double>(viewed - sent) / 1e6);
  }
  // Time-weighted mean of the full compressed grid over [first send, last scan seen].
  double integral = 0;
  std::int64_t prev_ns = first_sent;
  std::uint64_t prev_grid = 0;
  for (const UpdateSample& s : res.series) {
    if (s.ns > last_ns) break;
    integral += static_cast<double>(prev_grid) * static_cast<double>(s.ns - prev_ns) / 1e9;
    prev_ns = s.ns;
    prev_grid = s.grid_bytes;
  }
  integral += static_cast<double>(prev_grid) * static_cast<double>(std::max<std::int64_t>(0, last_ns - prev_ns)) / 1e9;
  res.grid_bytes_mean = res.wall_s > 0 ? integral / res.wall_s : 0.0;
  std::uint64_t delta_in_window = 0, updates_in_window = 0;
  for (const UpdateSample& s : res.series) {
    if (s.ns > last_ns) break;
    delta_in_window = s.delta_bytes;
    ++updates_in_window;
  }
  res.delta_bytes_per_s = res.wall_s > 0 ? static_cast<double>(delta_in_window) / res.wall_s : 0.0;
  res.updates_per_s = res.wall_s > 0 ? static_cast<double>(updates_in_window) / res.wall_s : 0.0;
  std::cerr << "[" << spec.label << "] done: " << res.viewed << "/" << spec.count << " scans seen processed in "
            << std::setprecision(1) << res.wall_s << " s (sent " << res.sent << ", acked " << res.acked << ")"
            << (res.agent_error.empty() ? "" : "; agent: " + res.agent_error) << "\n";
  return res;
}

// ---------------------------------------------------------------------------------------------
// map.png and friends.

struct PngResult {
  std::string label, session_id;
  int requests = 0, ok = 0;
  std::vector<double> png_ms, meta_ms, pgm_ms;
  std::size_t png_bytes = 0, pgm_bytes = 0;
  int width = 0, height = 0, tiles = 0;
  double server_cpu_s = 0;
};

PngResult MeasurePng(ServerProcess& server, const std::string& id, const std::string& label, int n) {
  PngResult r;
  r.label = label;
  r.session_id = id;
  r.requests = n;
  const auto deadline = Clock::now() + 300s;
  const double cpu0 = server.CpuSeconds();
  const std::string base = "/api/sessions/" + id;
  for (int i = 0; i < n && Clock::now() < deadline; ++i) {
    const HttpResult h = HttpGet(server.port(), base + "/map.png", 30s);
    if (h.status != 200) continue;
    ++r.ok;
    r.png_ms.push_back(h.ms);
    r.png_bytes = h.body.size();
    if (h.body.size() >= 24 && h.body.compare(1, 3, "PNG") == 0) {
      auto be32 = [&](std::size_t at) {
        const auto* b = reinterpret_cast<const unsigned char*>(h.body.data() + at);
        return static_cast<int>((b[0] << 24) | (b[1] << 16) | (b[2] << 8) | b[3]);
      };
      r.width = be32(16);
      r.height = be32(20);
    }
  }
  r.server_cpu_s = server.CpuSeconds() - cpu0;
  // For attribution: the same map as JSON metadata (grid + image geometry, no pixels) and as PGM
  // (rendered pixels, no deflate).
  for (int i = 0; i < 20 && Clock::now() < deadline; ++i) {
    const HttpResult meta = HttpGet(server.port(), base + "/map", 30s);
    if (meta.status == 200) {
      r.meta_ms.push_back(meta.ms);
      const json j = json::parse(meta.body, nullptr, false);
      if (j.is_object() && j.contains("tiles")) r.tiles = static_cast<int>(j["tiles"].size());
    }
    const HttpResult pgm = HttpGet(server.port(), base + "/map.pgm", 30s);
    if (pgm.status == 200) {
      r.pgm_ms.push_back(pgm.ms);
      r.pgm_bytes = pgm.body.size();
    }
  }
  std::cerr << "[png] " << label << ": " << r.ok << "/" << n << " ok, p50 " << Percentile(r.png_ms, 50) << " ms, p95 "
            << Percentile(r.png_ms, 95) << " ms, " << r.width << "x" << r.height << ", " << r.png_bytes << " bytes\n";
  return r;
}

struct ReplayResult {
  bool ran = false, finished = false;
  std::string session_id, status, error;
  std::int64_t scans = 0;
  double seconds = 0;
};

ReplayResult ReplayLog(unsigned short port, const Options& o) {
  ReplayResult r;
  r.ran = true;
  json settings = {{"particles", o.particles}};
  if (!o.predict.empty()) settings["predict"] = o.predict == "on";
  const json body = {{"log", std::filesystem::path(o.log).filename().string()}, {"speed", 0}, {"name", "bench replay"},
                     {"settings", settings}};
  const auto start = Clock::now();
  const HttpResult created = HttpPost(port, "/api/replays", body.dump());
  if (created.status != 201) {
    r.error = "POST /api/replays: " + std::to_string(created.status) + " " + created.body + created.error;
    return r;
  }
  r.session_id = json::parse(created.body).at("id").get<std::string>();
  std::cerr << "[replay] session " << r.session_id << ": the whole log, flat out\n";
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.replay_timeout_s));
  auto last_progress = start;
  while (Clock::now() < deadline) {
    std::this_thread::sleep_for(1s);
    const HttpResult s = HttpGet(port, "/api/sessions/" + r.session_id, 10s);
    if (s.status != 200) continue;
    const json j = json::parse(s.body, nullptr, false);
    if (!j.is_object()) continue;
    r.status = j.value("status", "");
    r.scans = j.value("scans", std::int64_t{0});
    if (r.status != "active") {
      r.finished = r.status == "closed";
      break;
    }
    if (Clock::now() - last_progress >= 10s) {
      last_progress = Clock::now();
      const HttpResult st = HttpGet(port, "/api/sessions/" + r.session_id + "/stats", 10s);
      const json sj = json::parse(st.body, nullptr, false);
      std::cerr << "[replay] " << static_cast<int>(SecondsBetween(start, Clock::now())) << " s: "
                << (sj.is_object() && sj.contains("filter") ? sj["filter"].value("scans", 0) : 0) << " scans filtered\n";
    }
  }
  r.seconds = SecondsBetween(start, Clock::now());
  if (!r.finished && r.error.empty()) r.error = "replay did not finish (status " + r.status + ")";
  std::cerr << "[replay] " << r.status << " after " << std::setprecision(1) << r.seconds << " s, " << r.scans << " scans\n";
  return r;
}

bool CloseSession(unsigned short port, const std::string& id) {
  return HttpPost(port, "/api/sessions/" + id + "/close", "", 120s).status == 200;
}

// ---------------------------------------------------------------------------------------------
// Reporting.

std::string Fmt(double v, int precision = 1) {
  if (std::isnan(v)) return "n/a";
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

double MedianRate(const std::vector<StatsSample>& samples, double skip_s, double until_s) {
  std::vector<double> v;
  for (const StatsSample& s : samples) {
    if (s.t >= skip_s && s.t <= until_s && s.rate_hz > 0) v.push_back(s.rate_hz);
  }
  return Percentile(v, 50);
}

json StreamJson(const StreamResult& r, double rate_hz) {
  json viewers = json::array();
  for (const ViewerResult& v : r.viewers) {
    viewers.push_back({{"mode", v.mode}, {"measured", v.measured}, {"connected", v.connected}, {"ended", v.ended},
                       {"messages", v.messages}, {"bytes", v.bytes}, {"delta_bytes", v.delta_bytes},
                       {"updates", v.updates}, {"error", v.error}});
  }
  json stats = json::array();
  for (const StatsSample& s : r.stats) {
    stats.push_back({{"t", s.t}, {"scan_rate_hz", s.rate_hz}, {"processed_seq", s.processed}, {"step_ms_mean", s.step_ms},
                     {"latency_ms_mean", s.latency_ms}, {"latency_ms_max", s.latency_max_ms},
                     {"prediction_ms_max", s.prediction_max_ms}, {"queued", s.queued}, {"last_commit_ms", s.commit_ms},
                     {"max_commit_ms", s.max_commit_ms}});
  }
  return {{"label", r.label},
          {"session_id", r.session_id},
          {"scans", r.scans},
          {"speed", r.speed},
          {"complete", r.complete},
          {"scans_seen_processed", r.viewed},
          {"wall_s", r.wall_s},
          {"input_rate_hz", std::isnan(r.input_rate_hz) ? json() : json(r.input_rate_hz)},
          {"processed_per_wall_s", r.processed_per_s},
          {"stats_scan_rate_hz_median", std::isnan(rate_hz) ? json() : json(rate_hz)},
          {"latency_ms", {{"p50", Percentile(r.latency_ms, 50)}, {"p95", Percentile(r.latency_ms, 95)},
                          {"p99", Percentile(r.latency_ms, 99)}, {"max", Max(r.latency_ms)}, {"mean", Mean(r.latency_ms)},
                          {"n", r.latency_ms.size()}}},
          {"ack_ms", {{"p50", Percentile(r.ack_ms, 50)}, {"p95", Percentile(r.ack_ms, 95)}, {"max", Max(r.ack_ms)}}},
          {"measured_viewer", {{"delta_bytes_per_s", r.delta_bytes_per_s}, {"updates_per_s", r.updates_per_s},
                               {"grid_bytes_end", r.grid_bytes_end}, {"grid_tiles_end", r.grid_tiles_end},
                               {"grid_bytes_mean", r.grid_bytes_mean}, {"bytes_by_type", r.bytes_by_type},
                               {"count_by_type", r.count_by_type}}},
          {"server_cpu_s", r.server_cpu_s},
          {"bench_cpu_s", r.bench_cpu_s},
          {"server_threads", [&] {
             json list = json::array();
             for (const ThreadCpu& th : r.threads) {
               if (th.cpu_s > 0) list.push_back({{"tid", th.tid}, {"cpu_s", th.cpu_s}, {"new_in_run", th.new_in_run}});
             }
             return list;
           }()},
          {"latency_split_ms",
           {{"over_100ms_after_a_tick", {{"n", r.latency_after_idle_ms.size()}, {"p50", Percentile(r.latency_after_idle_ms, 50)},
                                                        {"p95", Percentile(r.latency_after_idle_ms, 95)}, {"max", Max(r.latency_after_idle_ms)}}},
            {"within_100ms_of_a_tick", {{"n", r.latency_within_tick_ms.size()}, {"p50", Percentile(r.latency_within_tick_ms, 50)},
                                                    {"p95", Percentile(r.latency_within_tick_ms, 95)}, {"max", Max(r.latency_within_tick_ms)}}}}},
          {"per_scan_ms", {{"sent", r.sent_ms}, {"acked", r.acked_ms}, {"viewed", r.viewed_ms}}},
          {"viewer_ticks_ms", r.tick_ms},
          {"agent_errors", r.agent_errors},
          {"overloaded", r.overloaded},
          {"agent_error", r.agent_error},
          {"agent_window_waits", r.window_waits},
          {"viewers", viewers},
          {"stats_samples", stats}};
}

json PngJson(const PngResult& p) {
  return {{"label", p.label}, {"session_id", p.session_id}, {"requests", p.requests}, {"ok", p.ok},
          {"png_ms", {{"p50", Percentile(p.png_ms, 50)}, {"p95", Percentile(p.png_ms, 95)}, {"max", Max(p.png_ms)}, {"min", Min(p.png_ms)}}},
          {"map_json_ms_p50", Percentile(p.meta_ms, 50)}, {"map_pgm_ms_p50", Percentile(p.pgm_ms, 50)},
          {"png_bytes", p.png_bytes}, {"pgm_bytes", p.pgm_bytes}, {"width", p.width}, {"height", p.height},
          {"tiles", p.tiles}, {"server_cpu_s", p.server_cpu_s}};
}

struct ViewerGroup {
  int n = 0;
  std::vector<double> msgs, kbytes, updates;
};

std::map<std::string, ViewerGroup> GroupViewers(const StreamResult& r) {
  std::map<std::string, ViewerGroup> groups;
  for (const ViewerResult& v : r.viewers) {
    if (!v.connected) continue;
    ViewerGroup& g = groups[v.measured ? "measured" : v.mode];
    ++g.n;
    g.msgs.push_back(static_cast<double>(v.messages) / r.wall_s);
    g.kbytes.push_back(static_cast<double>(v.bytes) / 1024.0 / r.wall_s);
    g.updates.push_back(static_cast<double>(v.updates) / r.wall_s);
  }
  return groups;
}

int Main(int argc, char** argv) {
  const Options o = ParseOptions(argc, argv);
  if (!std::filesystem::exists(o.server)) throw std::runtime_error("no server binary at " + o.server + " (build pslam-server)");
  if (!std::filesystem::exists(o.log)) throw std::runtime_error("no log at " + o.log);
  const std::size_t load = std::max(o.scans, o.phases.count("throughput") ? o.flat_out_scans : 0);
  std::cerr << "loading up to " << load << " scans of " << o.log << "\n";
  const LogData log = LoadScans(o.log, load);
  if (log.scans.size() < 2) throw std::runtime_error("the log has fewer than 2 scans");
  const std::size_t scans = std::min(o.scans, log.scans.size());
  const std::size_t flat_scans = std::min(o.flat_out_scans, log.scans.size());

  const std::filesystem::path root = o.data_root.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(o.data_root);
  const std::filesystem::path dir = root / ("pslam-server-bench-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "data");
  const std::filesystem::path server_log = dir / "server.log";
  std::vector<std::string> server_args = {"--replay-dir", std::filesystem::absolute(o.log).parent_path().string(),
                                          "--particles", std::to_string(o.particles)};
  if (!o.postgres.empty()) server_args.insert(server_args.end(), {"--postgres", o.postgres});
  const std::string load_before = LoadAverage();
  std::cerr << "server " << o.server << " (data " << dir << ", log " << server_log << "), load average " << load_before << "\n";
  json out = {{"command", [&] {
                 std::string c;
                 for (int i = 0; i < argc; ++i) c += (i ? " " : "") + std::string(argv[i]);
                 return c;
               }()},
              {"server", o.server},
              {"storage", o.postgres.empty() ? "sqlite" : "postgres"},
              {"log", o.log},
              {"particles", o.particles},
              {"predict", o.predict.empty() ? "server default" : o.predict},
              {"speed", o.speed},
              {"cores", std::thread::hardware_concurrency()},
              {"load_average_before", load_before}};

  std::optional<StreamResult> a, b, c1, c50;
  std::optional<PngResult> png_live, png_replay;
  ReplayResult replay;
  {
    ServerProcess server(o.server, dir / "data", server_args, server_log);
    const unsigned short port = server.port();
    const int others = o.viewers - 1 - o.slow_viewers - o.stalled_viewers;
    const RunSpec one{"1 viewer", scans, o.speed, 0, 0, 0, std::chrono::milliseconds(o.slow_delay_ms)};
    const RunSpec many{std::to_string(o.viewers) + " viewers", scans, o.speed, others, o.slow_viewers, o.stalled_viewers,
                       std::chrono::milliseconds(o.slow_delay_ms)};
    if (o.phases.count("latency") || o.phases.count("png")) {  // png also times the streamed session's map
      a = RunStream(o, server, log, one);
      if (o.phases.count("png")) png_live = MeasurePng(server, a->session_id, "streamed session (live)", o.png_requests);
      CloseSession(port, a->session_id);
    }
    if (o.phases.count("viewers")) {
      b = RunStream(o, server, log, many);
      CloseSession(port, b->session_id);
    }
    if (o.phases.count("throughput") && flat_scans >= 2) {
      RunSpec f1 = one, f50 = many;
      f1.label = "flat out, 1 viewer";
      f50.label = "flat out, " + std::to_string(o.viewers) + " viewers";
      f1.count = f50.count = flat_scans;
      f1.speed = f50.speed = 0;
      c1 = RunStream(o, server, log, f1);
      CloseSession(port, c1->session_id);
      c50 = RunStream(o, server, log, f50);
      CloseSession(port, c50->session_id);
    }
    if (o.phases.count("png") && o.replay) {
      replay = ReplayLog(port, o);
      if (replay.finished) png_replay = MeasurePng(server, replay.session_id, "whole log replayed (closed)", o.png_requests);
    }
    const int status = server.Stop();
    out["server_exit_status"] = status;
  }
  out["load_average_after"] = LoadAverage();

  // ------------------------------------------------------------------ results
  std::ostringstream t;
  auto rate_of = [](const StreamResult& r) { return MedianRate(r.stats, 6.0, r.wall_s); };
  json targets = json::array();
  auto target = [&](const std::string& name, const std::string& measured, const std::string& goal, std::optional<bool> met) {
    targets.push_back({{"target", name}, {"measured", measured}, {"goal", goal}, {"met", met ? json(*met) : json()}});
  };

  if (a) {
    out["latency_run"] = StreamJson(*a, rate_of(*a));
    const double p95 = Percentile(a->latency_ms, 95);
    target("scan-to-viewer latency p95", Fmt(p95) + " ms (p50 " + Fmt(Percentile(a->latency_ms, 50)) + ", max " + Fmt(Max(a->latency_ms)) + ")",
           "<= 100 ms", a->complete ? std::optional<bool>(p95 <= 100.0) : std::nullopt);
  }
  if (b) out["viewers_run"] = StreamJson(*b, rate_of(*b));
  if (c1) out["flat_out_1_viewer"] = StreamJson(*c1, rate_of(*c1));
  if (c50) out["flat_out_n_viewers"] = StreamJson(*c50, rate_of(*c50));
  if (a && b) {
    const double real_ratio = b->processed_per_s / a->processed_per_s;
    std::optional<bool> met = real_ratio >= 0.95 && a->complete && b->complete;
    std::string measured = "real time: " + Fmt(b->processed_per_s, 2) + " vs " + Fmt(a->processed_per_s, 2) + " scans/s (" +
                           Fmt(100 * real_ratio, 0) + "%)";
    if (c1 && c50) {
      const double flat_ratio = c50->processed_per_s / c1->processed_per_s;
      measured += "; flat out: " + Fmt(c50->processed_per_s, 0) + " vs " + Fmt(c1->processed_per_s, 0) + " scans/s (" +
                  Fmt(100 * flat_ratio, 0) + "%)";
      met = *met && flat_ratio >= 0.95 && c1->complete && c50->complete;
    }
    target(std::to_string(o.viewers) + " viewers: filter rate vs 1 viewer", measured, ">= 95% of the 1-viewer rate", met);
  }
  std::optional<double> png_end;
  if (png_live && png_live->ok) png_end = static_cast<double>(png_live->png_bytes);
  if (a) {
    const double grid_resend = a->grid_bytes_mean * 10.0;
    const double ratio = grid_resend > 0 ? a->delta_bytes_per_s / grid_resend : std::nan("");
    std::string measured = Fmt(a->delta_bytes_per_s / 1024.0, 1) + " KiB/s vs full grid " + Fmt(grid_resend / 1024.0, 1) +
                           " KiB/s = " + Fmt(100 * ratio, 1) + "%";
    if (png_end) measured += "; vs full PNG at the end x 10 Hz: " + Fmt(100 * a->delta_bytes_per_s / (*png_end * 10.0), 1) + "%";
    target("live bytes vs full-grid resend at 10 Hz", measured, "<= 10%", std::isnan(ratio) ? std::nullopt : std::optional<bool>(ratio <= 0.10));
    out["live_bytes"] = {{"delta_bytes_per_s", a->delta_bytes_per_s},
                         {"grid_bytes_mean", a->grid_bytes_mean},
                         {"grid_bytes_end", a->grid_bytes_end},
                         {"png_bytes_end", png_end ? json(*png_end) : json()},
                         {"ratio_vs_grid_mean_10hz", ratio},
                         {"ratio_vs_grid_end_10hz", a->grid_bytes_end ? a->delta_bytes_per_s / (a->grid_bytes_end * 10.0) : std::nan("")},
                         {"ratio_vs_png_end_10hz", png_end ? json(a->delta_bytes_per_s / (*png_end * 10.0)) : json()},
                         {"ratio_vs_grid_mean_at_update_rate", a->updates_per_s > 0 && a->grid_bytes_mean > 0
                                                                   ? a->delta_bytes_per_s / (a->grid_bytes_mean * a->updates_per_s)
                                                                   : std::nan("")}};
  }
  const PngResult* intel_png = png_replay ? &*png_replay : png_live ? &*png_live : nullptr;
  if (intel_png) {
    const double p95 = Percentile(intel_png->png_ms, 95);
    target("map.png p95 (" + intel_png->label + ", " + std::to_string(intel_png->width) + "x" + std::to_string(intel_png->height) + ")",
           Fmt(p95) + " ms (p50 " + Fmt(Percentile(intel_png->png_ms, 50)) + ")", "<= 50 ms",
           intel_png->ok ? std::optional<bool>(p95 <= 50.0) : std::nullopt);
  }
  if (png_live) out["png_streamed_session"] = PngJson(*png_live);
  if (png_replay) out["png_replayed_log"] = PngJson(*png_replay);
  if (replay.ran) {
    out["replay"] = {{"session_id", replay.session_id}, {"finished", replay.finished}, {"status", replay.status},
                     {"scans", replay.scans}, {"seconds", replay.seconds}, {"error", replay.error}};
  }
  out["targets"] = targets;

  // The table (markdown, so that it can go into the README as is).
  t << "\n## pslam-server-bench results\n\n";
  t << "Log " << std::filesystem::path(o.log).filename().string() << ", " << o.particles << " particles, predict "
    << (o.predict.empty() ? "server default" : o.predict) << ", " << std::thread::hardware_concurrency()
    << " cores, load average before " << load_before << ", after " << out["load_average_after"].get<std::string>() << ".\n\n";
  t << "| target | measured | goal | met |\n| --- | --- | --- | --- |\n";
  for (const json& row : targets) {
    t << "| " << row["target"].get<std::string>() << " | " << row["measured"].get<std::string>() << " | "
      << row["goal"].get<std::string>() << " | " << (row["met"].is_null() ? "n/a" : row["met"].get<bool>() ? "yes" : "**no**") << " |\n";
  }
  auto run_row = [&](const StreamResult& r) {
    t << "| " << r.label << " | " << r.viewed << "/" << r.scans << " | " << Fmt(r.wall_s) << " | "
      << Fmt(r.input_rate_hz, 2) << " | " << Fmt(r.processed_per_s, 2) << " | " << Fmt(rate_of(r), 2) << " | "
      << Fmt(Percentile(r.latency_ms, 50)) << " / " << Fmt(Percentile(r.latency_ms, 95)) << " / " << Fmt(Max(r.latency_ms))
      << " | " << Fmt(Percentile(r.ack_ms, 50)) << " / " << Fmt(Percentile(r.ack_ms, 95)) << " | "
      << Fmt(r.updates_per_s) << " | " << Fmt(r.delta_bytes_per_s / 1024.0) << " | "
      << Fmt(100.0 * r.server_cpu_s / std::max(r.wall_s, 1e-9), 0) << "% | "
      << Fmt(100.0 * r.bench_cpu_s / std::max(r.wall_s, 1e-9), 0) << "% |\n";
  };
  t << "\n| run | scans seen | wall s | input scans/s | processed scans/s | stats scan_rate_hz (median) | "
       "latency ms p50 / p95 / max | ack ms p50 / p95 | live ticks/s | viewer KiB/s | server CPU | bench CPU |\n"
       "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const auto* r : {a ? &*a : nullptr, b ? &*b : nullptr, c1 ? &*c1 : nullptr, c50 ? &*c50 : nullptr}) {
    if (r) run_row(*r);
  }
  t << "\nServer threads, CPU as % of the run's wall time (E: started during the run, the session's engine):";
  for (const auto* r : {a ? &*a : nullptr, b ? &*b : nullptr, c1 ? &*c1 : nullptr, c50 ? &*c50 : nullptr}) {
    if (!r) continue;
    t << "\n- " << r->label << ":";
    int shown = 0;
    double rest = 0;
    for (const ThreadCpu& th : r->threads) {
      if (shown < 4 && th.cpu_s > 0) {
        t << " " << Fmt(100.0 * th.cpu_s / std::max(r->wall_s, 1e-9), 1) << "%" << (th.new_in_run ? " (E)" : "") << ",";
        ++shown;
      } else {
        rest += th.cpu_s;
      }
    }
    t << " others " << Fmt(100.0 * rest / std::max(r->wall_s, 1e-9), 1) << "%";
  }
  t << "\n";
  if (a) {
    t << "\nLatency of the " << a->label << " run, scans sent with no live tick in the 100 ms before: p50 "
      << Fmt(Percentile(a->latency_after_idle_ms, 50)) << " / p95 "
      << Fmt(Percentile(a->latency_after_idle_ms, 95)) << " / max " << Fmt(Max(a->latency_after_idle_ms)) << " ms, "
      << a->latency_after_idle_ms.size() << " scans; scans sent less than 100 ms after a tick (a fixed 100 ms spacing "
      << "would hold them until the next tick): p50 "
      << Fmt(Percentile(a->latency_within_tick_ms, 50)) << " / p95 " << Fmt(Percentile(a->latency_within_tick_ms, 95))
      << " / max " << Fmt(Max(a->latency_within_tick_ms)) << " ms, " << a->latency_within_tick_ms.size() << " scans.\n";
  }
  if (b) {
    t << "\nPer-viewer receive rate in the " << b->label << " run (min / median / max per viewer):\n\n"
      << "| viewers | n | messages/s | KiB/s | live ticks/s |\n| --- | --- | --- | --- | --- |\n";
    for (const auto& [name, g] : GroupViewers(*b)) {
      t << "| " << name << " | " << g.n << " | " << Fmt(Min(g.msgs)) << " / " << Fmt(Percentile(g.msgs, 50)) << " / "
        << Fmt(Max(g.msgs)) << " | " << Fmt(Min(g.kbytes)) << " / " << Fmt(Percentile(g.kbytes, 50)) << " / "
        << Fmt(Max(g.kbytes)) << " | " << Fmt(Min(g.updates), 2) << " / " << Fmt(Percentile(g.updates, 50), 2) << " / "
        << Fmt(Max(g.updates), 2) << " |\n";
    }
    int dropped = 0;
    for (const ViewerResult& v : b->viewers) dropped += v.connected && v.ended ? 1 : 0;
    if (dropped) t << "\n" << dropped << " viewer socket(s) were closed by the server during the run.\n";
  }
  if (a) {
    t << "\nLive bytes of the measured viewer (" << a->label << " run), by message type: ";
    std::uint64_t total = 0;
    for (const auto& [type, bytes] : a->bytes_by_type) total += bytes;
    bool first = true;
    for (const auto& [type, bytes] : a->bytes_by_type) {
      t << (first ? "" : ", ") << type << " " << Fmt(100.0 * static_cast<double>(bytes) / std::max<double>(1.0, total), 0) << "% ("
        << a->count_by_type.at(type) << " msgs)";
      first = false;
    }
    t << ". Full compressed grid: " << Fmt(a->grid_bytes_mean / 1024.0) << " KiB mean over the run, "
      << Fmt(a->grid_bytes_end / 1024.0) << " KiB (" << a->grid_tiles_end << " tiles) at the end";
    if (png_end) t << "; map.png at the end " << Fmt(*png_end / 1024.0) << " KiB";
    t << ".\n";
  }
  if (png_live || png_replay) {
    t << "\n| map | size px | tiles | PNG bytes | map.png ms p50 / p95 / max | /map (JSON) ms p50 | map.pgm ms p50 |\n"
         "| --- | --- | --- | --- | --- | --- | --- |\n";
    for (const auto* p : {png_live ? &*png_live : nullptr, png_replay ? &*png_replay : nullptr}) {
      if (!p) continue;
      t << "| " << p->label << " | " << p->width << "x" << p->height << " | " << p->tiles << " | " << p->png_bytes << " | "
        << Fmt(Percentile(p->png_ms, 50)) << " / " << Fmt(Percentile(p->png_ms, 95)) << " / " << Fmt(Max(p->png_ms)) << " | "
        << Fmt(Percentile(p->meta_ms, 50)) << " | " << Fmt(Percentile(p->pgm_ms, 50)) << " |\n";
    }
  }
  if (replay.ran) {
    t << "\nReplay of the whole log (POST /api/replays, speed 0): " << (replay.finished ? "closed" : "not finished") << " after "
      << Fmt(replay.seconds) << " s, " << replay.scans << " scans" << (replay.error.empty() ? "" : " (" + replay.error + ")") << ".\n";
  }
  if (o.json_stdout) {
    std::cerr << t.str();
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << t.str();
  }
  if (!o.json_file.empty()) std::ofstream(o.json_file) << out.dump(2) << "\n";
  if (!o.keep) {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  } else {
    std::cerr << "kept " << dir << "\n";
  }
  return 0;
}

}  // namespace
}  // namespace pslam::bench

int main(int argc, char** argv) {
  try {
    return pslam::bench::Main(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "pslam-server-bench: " << e.what() << "\n";
    return 1;
  }
}
