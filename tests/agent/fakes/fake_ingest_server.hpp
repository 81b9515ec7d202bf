#pragma once
// A minimal but faithful peer of schema/ws/ingest.md for agent tests and the benchmark, standing in
// for pslam-server: checks the bearer token on the upgrade (HTTP 401, or the in-band variant: error
// "unauthorized" + close 1008), answers hello with welcome (new or resumed session, last_acked_seq),
// stores messages "durably" in batches and acknowledges them cumulatively, ignores (but re-acks)
// duplicates, and can send targets. Kill() drops every connection and whatever was received but not
// yet committed, like a crashed server; Start() on the same port brings it back, store intact.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace pslam::agent::testing {

struct StoredMessage {
  std::uint64_t seq = 0;
  std::string type;  // "odom" or "scan"
  double t = 0.0;
  std::size_t ranges = 0;
  std::size_t null_ranges = 0;
  bool binary = false;
  double x = 0.0, y = 0.0, theta = 0.0, v = 0.0;  // odometry (odom: pose and speed; scan: the interpolated pose)
};

struct FakeSession {
  std::vector<StoredMessage> committed;  // exactly once per seq if the agent behaves
  std::uint64_t last_acked = 0;
  std::size_t duplicates = 0;            // received again after being stored (re-acked, not stored)
  std::size_t gaps = 0;                  // a seq that skipped ahead (a protocol error by the agent)
  std::size_t bad_messages = 0;
  nlohmann::json hello;
};

struct FakeIngestOptions {
  std::string token = "secret";
  bool refuse_in_band = false;    // bad token: accept the upgrade, send error "unauthorized", close 1008
  double commit_period_s = 0.02;  // acks go out when a batch is committed
};

// Beast stays in fake_ingest_server.cpp, compiled once.
class FakeIngestServer {
 public:
  explicit FakeIngestServer(FakeIngestOptions options = {});
  ~FakeIngestServer();
  FakeIngestServer(const FakeIngestServer&) = delete;
  FakeIngestServer& operator=(const FakeIngestServer&) = delete;

  // Listens on 127.0.0.1:'port' (0: a free port). Returns the port.
  unsigned short Start(unsigned short port = 0);
  // Abrupt stop: sockets closed without a close frame, uncommitted messages lost.
  void Kill();

  unsigned short port() const;
  // A silent server: nothing is committed or acknowledged while off.
  void set_acks_enabled(bool on);
  void SendToAll(const nlohmann::json& message);

  std::map<std::string, FakeSession> sessions();
  std::size_t welcomes();
  std::size_t refused();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pslam::agent::testing
