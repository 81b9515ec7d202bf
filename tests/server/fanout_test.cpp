// Live fan-out through Redis: two real pslam-server processes on one PostgreSQL and one Redis
// (started on loopback by deploy/cluster/services.sh). A viewer on node B watches a session that
// an agent maps on node A and gets the same map as A's own viewers; a later viewer on B gets the
// snapshot at once; when A dies (kill -9) B's viewer keeps its socket and carries on once a node
// runs the session again. Node B starts before the session exists, so it never resumes it itself.
#include <gtest/gtest.h>

#include <boost/asio.hpp>

#include <atomic>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "common/zlib_codec.hpp"
#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"
#include "server/support/test_services.hpp"

namespace pslam::server::testing {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

// What one viewer has been shown: the latest frame per tile, the latest pose and stats.
struct Picture {
  std::map<std::pair<int, int>, std::string> tiles;
  nlohmann::json pose, stats, snapshot;
  std::string status;  // of a `session` message
  int snapshots = 0;

  void Take(const WsMessage& m) {
    if (m.binary) {
      if (m.data.compare(0, 4, "PSTL") != 0) return;
      std::int32_t x = 0, y = 0;
      std::memcpy(&x, m.data.data() + 4, 4);
      std::memcpy(&y, m.data.data() + 8, 4);
      tiles[{x, y}] = m.data;
      return;
    }
    const auto j = m.Json();
    const std::string type = j.value("type", "");
    if (type == "snapshot") {
      ++snapshots;
      snapshot = j;
      tiles.clear();
      if (!j["pose"].is_null()) pose = j["pose"];
      stats = j["stats"];
    } else if (type == "pose") {
      pose = j;
    } else if (type == "stats") {
      stats = j["stats"];
    } else if (type == "session") {
      status = j["status"];
    }
  }
  std::int64_t processed() const { return stats.is_object() ? stats.value("processed_seq", std::int64_t{0}) : 0; }
};

// Reads 'ws' into 'picture' until 'done' holds; false on timeout or a closed socket.
template <typename Done>
bool ReadUntil(WsClient& ws, Picture& picture, Done done, std::chrono::seconds timeout = std::chrono::seconds(30)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done(picture)) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    auto m = ws.Read(left);
    if (!m) return false;
    picture.Take(*m);
  }
  return true;
}

std::vector<std::uint8_t> Cells(const std::string& frame) {
  const auto* payload = reinterpret_cast<const std::uint8_t*>(frame.data()) + 24;
  auto cells = ZlibDecompress({payload, frame.size() - 24}, 64 * 64);
  return cells ? *cells : std::vector<std::uint8_t>{};
}

void ExpectSameMap(const Picture& owner, const Picture& remote) {
  ASSERT_FALSE(owner.tiles.empty());
  ASSERT_EQ(owner.tiles.size(), remote.tiles.size());
  for (const auto& [key, frame] : owner.tiles) {
    const auto it = remote.tiles.find(key);
    ASSERT_NE(it, remote.tiles.end()) << "tile " << key.first << "," << key.second;
    const auto cells = Cells(frame);
    ASSERT_EQ(cells.size(), 64u * 64u);
    EXPECT_EQ(cells, Cells(it->second)) << "tile " << key.first << "," << key.second;
  }
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A loopback port nobody listens on (bound, then released).
unsigned short FreePort() {
  asio::io_context ioc;
  tcp::acceptor acceptor(ioc, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  return acceptor.local_endpoint().port();
}

// A Redis server of the test's own on 'port', stopped at scope exit.
class OwnRedis {
 public:
  OwnRedis(const std::filesystem::path& dir, unsigned short port) : pidfile_(dir / "redis.pid") {
    const std::string start = "redis-server --bind 127.0.0.1 --port " + std::to_string(port) +
                              " --save '' --appendonly no --daemonize yes --dir " + dir.string() + " --pidfile " +
                              pidfile_.string() + " --logfile " + (dir / "redis.log").string();
    if (std::system(start.c_str()) != 0) throw std::runtime_error("cannot start " + start);
    const std::string ping = "redis-cli -p " + std::to_string(port) + " ping 2>/dev/null | grep -q PONG";
    for (int i = 0; i < 100 && std::system(ping.c_str()) != 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ~OwnRedis() {
    const std::string stop = "kill $(cat " + pidfile_.string() + ") 2>/dev/null";
    (void)std::system(stop.c_str());
  }

 private:
  std::filesystem::path pidfile_;
};

class FanoutTest : public ::testing::Test {
 protected:
  std::vector<std::string> NodeArgs(const std::string& redis = TestRedisUrl()) const {
    return {"--postgres", postgres_.url(), "--redis", redis, "--particles", "4", "--predict", "off"};
  }
  // Until A's REST says the filter has processed 'seq' (scans are acknowledged when stored).
  static bool WaitProcessed(unsigned short port, const std::string& id, std::int64_t seq) {
    for (int i = 0; i < 400; ++i) {
      if (Get(port, "/api/sessions/" + id + "/stats").Json()["filter"]["processed_seq"] == seq) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

  TempDir dir_;
  TestPostgresDatabase postgres_;
};

TEST_F(FanoutTest, AViewerOnAnotherNodeSeesTheOwnersMapPoseAndStats) {
  ServerProcess b(dir_.path() / "b", NodeArgs());
  ServerProcess a(dir_.path() / "a", NodeArgs());
  WsClient agent(a.port(), "/api/ingest");
  agent.SendJson(Hello());
  const std::string id = (*agent.ReadType("welcome"))["session_id"];

  WsClient on_a(a.port(), "/api/sessions/" + id + "/live");
  WsClient on_b(b.port(), "/api/sessions/" + id + "/live");
  ASSERT_TRUE(on_a.open() && on_b.open());
  Picture seen_a, seen_b;
  for (std::int64_t seq = 1; seq <= 40; ++seq) SendScan(agent, seq, seq % 2 == 0);
  ASSERT_EQ(WaitForAck(agent, 40), 40);
  ASSERT_TRUE(WaitProcessed(a.port(), id, 40));
  // B's viewer gets the ticks through Redis: the pose and stats of the last scan, and tiles.
  ASSERT_TRUE(ReadUntil(on_b, seen_b, [](const Picture& p) { return p.processed() == 40 && !p.tiles.empty(); }))
      << "B's viewer saw processed_seq " << seen_b.processed();
  ASSERT_TRUE(ReadUntil(on_a, seen_a, [](const Picture& p) { return p.processed() == 40; }));

  // A viewer joining B later gets the live picture at once (particles: it is not storage's).
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the last ticks reached B's mirror
  WsClient late_b(b.port(), "/api/sessions/" + id + "/live");
  WsClient late_a(a.port(), "/api/sessions/" + id + "/live");
  Picture snap_b, snap_a;
  auto whole = [](const Picture& p) { return p.snapshots == 1 && p.tiles.size() == p.snapshot["tile_count"].get<std::size_t>(); };
  ASSERT_TRUE(ReadUntil(late_b, snap_b, whole, std::chrono::seconds(5)));
  ASSERT_TRUE(ReadUntil(late_a, snap_a, whole, std::chrono::seconds(5)));
  EXPECT_EQ(snap_b.snapshot["status"], "active");
  EXPECT_EQ(snap_b.snapshot["particles"].size(), 4u);
  EXPECT_EQ(snap_b.snapshot["pose"], snap_a.snapshot["pose"]);
  EXPECT_EQ(snap_b.snapshot["trajectory"]["poses"].size(), 40u);
  EXPECT_EQ(snap_b.processed(), 40);
  ExpectSameMap(snap_a, snap_b);

  // Garbage on the session's channel is dropped with a log line; B serves on.
  const std::string garbage = "redis-cli -u " + TestRedisUrl() + " PUBLISH pslam:live:" + id + " not-an-envelope >/dev/null";
  ASSERT_EQ(std::system(garbage.c_str()), 0);

  // Closing the session on A: every viewer, on either node, is told and holds the same map.
  ASSERT_EQ(Post(a.port(), "/api/sessions/" + id + "/close", "").status, 200);
  auto ended = [](const Picture& p) { return !p.status.empty(); };
  ASSERT_TRUE(ReadUntil(on_a, seen_a, ended));
  ASSERT_TRUE(ReadUntil(on_b, seen_b, ended));
  EXPECT_EQ(seen_b.status, "closed");
  EXPECT_EQ(seen_b.snapshots, 1);  // the one on subscribe; the rest came as deltas
  ExpectSameMap(seen_a, seen_b);
  EXPECT_EQ(seen_b.pose["x"], seen_a.pose["x"]);
  EXPECT_EQ(seen_b.pose["y"], seen_a.pose["y"]);
  EXPECT_NE(ReadFile(b.log_path()).find("dropped a bad message"), std::string::npos);
}

TEST_F(FanoutTest, ARemoteViewerOutlivesItsOwnerAndContinuesWithTheNext) {
  ServerProcess b(dir_.path() / "b", NodeArgs());
  auto a = std::make_unique<ServerProcess>(dir_.path() / "a", NodeArgs());
  std::string id;
  {
    WsClient agent(a->port(), "/api/ingest");
    agent.SendJson(Hello());
    id = (*agent.ReadType("welcome"))["session_id"];
    for (std::int64_t seq = 1; seq <= 20; ++seq) SendScan(agent, seq, false);
    ASSERT_EQ(WaitForAck(agent, 20), 20);
  }
  WsClient viewer(b.port(), "/api/sessions/" + id + "/live");
  Picture seen;
  ASSERT_TRUE(ReadUntil(viewer, seen, [](const Picture& p) { return p.processed() == 20 && !p.tiles.empty(); }));

  a->Kill9();
  // A new node over the same storage resumes the session (it was left active) and takes the agent.
  ServerProcess a2(dir_.path() / "a2", NodeArgs());
  WsClient agent(a2.port(), "/api/ingest");
  agent.SendJson(Hello(id));
  ASSERT_TRUE(agent.ReadType("welcome"));
  for (std::int64_t seq = 21; seq <= 40; ++seq) SendScan(agent, seq, false);
  ASSERT_EQ(WaitForAck(agent, 40), 40);
  // The same socket on B shows the new owner's ticks.
  ASSERT_TRUE(ReadUntil(viewer, seen, [](const Picture& p) { return p.processed() == 40; }))
      << "B's viewer saw processed_seq " << seen.processed() << ", closed: " << viewer.closed();
  EXPECT_TRUE(seen.status.empty());  // never told the session ended
  EXPECT_FALSE(seen.tiles.empty());
}

TEST_F(FanoutTest, MappingGoesOnWhileRedisIsDownAndFanOutResumesWhenItIsBack) {
  const unsigned short port = FreePort();
  const std::string redis = "redis://127.0.0.1:" + std::to_string(port);
  ServerProcess b(dir_.path() / "b", NodeArgs(redis));
  ServerProcess a(dir_.path() / "a", NodeArgs(redis));
  WsClient agent(a.port(), "/api/ingest");
  agent.SendJson(Hello());
  const std::string id = (*agent.ReadType("welcome"))["session_id"];
  WsClient remote(b.port(), "/api/sessions/" + id + "/live");
  for (std::int64_t seq = 1; seq <= 20; ++seq) SendScan(agent, seq, false);
  ASSERT_EQ(WaitForAck(agent, 20), 20);
  ASSERT_TRUE(WaitProcessed(a.port(), id, 20));  // the filter does not wait for Redis
  WsClient local(a.port(), "/api/sessions/" + id + "/live");
  Picture seen_local;
  ASSERT_TRUE(ReadUntil(local, seen_local, [](const Picture& p) { return p.processed() == 20 && !p.tiles.empty(); }));
  EXPECT_NE(ReadFile(a.log_path()).find("cannot connect to Redis"), std::string::npos);

  // Redis comes up: both nodes reconnect (back-off of at most 5 s) and B's viewer follows A.
  const auto redis_dir = dir_.path() / "redis";
  std::filesystem::create_directories(redis_dir);
  OwnRedis server(redis_dir, port);
  std::atomic<bool> stop{false};
  std::thread robot([&] {  // keeps mapping, a scan every 100 ms
    for (std::int64_t seq = 21; seq <= 300 && !stop; ++seq) {
      SendScan(agent, seq, false);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  Picture seen;  // storage's snapshot says 20; more can only come through Redis
  const bool followed = ReadUntil(remote, seen, [](const Picture& p) { return p.processed() > 25 && !p.tiles.empty(); });
  stop = true;
  robot.join();
  ASSERT_TRUE(followed) << "B's viewer saw processed_seq " << seen.processed();
  EXPECT_TRUE(seen.status.empty());
}

}  // namespace
}  // namespace pslam::server::testing
