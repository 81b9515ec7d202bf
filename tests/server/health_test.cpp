// /api/health says "degraded", with the reason, when storage writes fail (here: the data directory's
// file system is full), instead of "ok" while nothing can be stored.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

// A small tmpfs of its own, so filling it touches nothing else; unmounted at scope exit.
class SmallFileSystem {
 public:
  SmallFileSystem(const std::filesystem::path& where, const std::string& size) : path_(where) {
    std::filesystem::create_directories(path_);
    mounted_ = ::mount("tmpfs", path_.c_str(), "tmpfs", 0, ("size=" + size).c_str()) == 0;
  }
  ~SmallFileSystem() {
    if (mounted_) ::umount2(path_.c_str(), MNT_DETACH);
  }
  bool mounted() const { return mounted_; }

 private:
  std::filesystem::path path_;
  bool mounted_ = false;
};

// Writes a file until the file system refuses more.
void Fill(const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary);
  const std::vector<char> block(64 * 1024, 'x');
  while (out.write(block.data(), static_cast<std::streamsize>(block.size()))) out.flush();
}

TEST(HealthTest, FullDiskMakesTheServerDegraded) {
  if (geteuid() != 0) GTEST_SKIP() << "mounting a small tmpfs needs root";
  TempDir dir;
  SmallFileSystem disk(dir.path() / "disk", "8m");
  ASSERT_TRUE(disk.mounted()) << "mount tmpfs failed";
  ServerProcess server(dir.path() / "disk" / "data");
  const unsigned short port = server.port();
  EXPECT_EQ(Get(port, "/api/health").Json()["status"], "ok");

  WsClient agent(port, "/api/ingest");
  agent.SendJson(Hello());
  ASSERT_TRUE(agent.ReadType("welcome"));
  ASSERT_TRUE(SendScan(agent, 1, true));
  ASSERT_EQ(WaitForAck(agent, 1), 1);

  Fill(dir.path() / "disk" / "filler");
  // Writes now fail: the agent is told, and so is whoever watches the health.
  for (std::int64_t seq = 2; seq <= 40 && agent.open(); ++seq) SendScan(agent, seq, true);
  nlohmann::json health;
  for (int i = 0; i < 100; ++i) {
    health = Get(port, "/api/health").Json();
    if (health["status"] != "ok") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(health["status"], "degraded") << health.dump();
  ASSERT_TRUE(health.contains("reasons")) << health.dump();
  EXPECT_NE(health["reasons"][0].get<std::string>().find("storage writes are failing"), std::string::npos)
      << health.dump();
  EXPECT_GT(health["storage"]["failed_jobs"].get<int>(), 0);
}

}  // namespace
}  // namespace pslam::server::testing
