// Out of file descriptors, the server waits for connections to close instead of retrying accept()
// in a busy loop (which burned a core and wrote a log line per attempt), and serves again once
// they have closed.
#include <gtest/gtest.h>

#include <boost/asio.hpp>
#include <sys/resource.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

// User + system CPU time of a process, in seconds (/proc/PID/stat fields 14 and 15).
double CpuSeconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // the name may hold spaces
  std::string skip;
  for (int i = 3; i < 14; ++i) fields >> skip;
  double user = 0, system = 0;
  fields >> user >> system;
  return (user + system) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

std::size_t OpenDescriptors(pid_t pid) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd")) ++n;
  return n;
}

std::size_t CountLines(const std::filesystem::path& file, const std::string& needle) {
  std::ifstream in(file);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) n += line.find(needle) != std::string::npos ? 1 : 0;
  return n;
}

TEST(DescriptorExhaustionTest, AcceptBacksOffAndRecoversWhenConnectionsClose) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  ASSERT_EQ(Get(server.port(), "/api/health").status, 200);
  // A few descriptors to spare, then none: the server's own limit, as a small LimitNOFILE would set it.
  const rlim_t limit = OpenDescriptors(server.pid()) + 8;
  const rlimit lowered{limit, limit};
  ASSERT_EQ(prlimit(server.pid(), RLIMIT_NOFILE, &lowered, nullptr), 0);

  asio::io_context ioc;
  std::vector<std::unique_ptr<tcp::socket>> clients;
  for (int i = 0; i < 40; ++i) {  // more than the server can take; the rest wait in its backlog
    auto socket = std::make_unique<tcp::socket>(ioc);
    socket->connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), server.port()));
    clients.push_back(std::move(socket));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let it run out
  const double cpu_before = CpuSeconds(server.pid());
  std::this_thread::sleep_for(std::chrono::seconds(3));
  const double cpu = CpuSeconds(server.pid()) - cpu_before;
  std::cout << "[ measure  ] server CPU while out of descriptors: " << cpu << " s in 3 s\n";
  EXPECT_LT(cpu, 0.3) << "the accept loop spins";  // it spun at 0.7-1 s per second
  // A line when an episode starts and one when it ends, not one per failed accept() (about 7 in
  // these 3.5 s with the back-off). A descriptor the server frees for a moment (a file it closes)
  // may end an episode and start another: allow two.
  EXPECT_LE(CountLines(server.log_path(), "pausing new connections"), 2u);
  EXPECT_LE(CountLines(server.log_path(), "accept:"), 4u);

  clients.clear();  // the server sees them close and frees their descriptors
  bool healthy = false;
  for (int i = 0; i < 50 && !healthy; ++i) {
    try {
      healthy = Get(server.port(), "/api/health").status == 200;
    } catch (const std::exception&) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  EXPECT_TRUE(healthy) << "no health answer after the connections closed";
  EXPECT_GE(CountLines(server.log_path(), "accepting again"), 1u);
}

}  // namespace
}  // namespace pslam::server::testing
