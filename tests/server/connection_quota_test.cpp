// WebSockets that never say hello, and viewers holding every slot, cannot lock agents out: agent
// sockets must say hello within a deadline, agents and viewers have separate quotas, and one
// token cannot take every slot.
#include <gtest/gtest.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <poll.h>

#include <memory>
#include <string>
#include <vector>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

using Socket = websocket::stream<beast::tcp_stream>;

// Many WebSockets on one io_context (a WsClient each would cost several descriptors apiece).
std::vector<std::unique_ptr<Socket>> OpenSockets(asio::io_context& ioc, unsigned short port, const std::string& target,
                                                 const std::string& token, int count) {
  std::vector<std::unique_ptr<Socket>> sockets;
  for (int i = 0; i < count; ++i) {
    auto ws = std::make_unique<Socket>(ioc);
    beast::get_lowest_layer(*ws).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
    ws->set_option(websocket::stream_base::decorator(
        [token](websocket::request_type& req) { req.set(http::field::authorization, "Bearer " + token); }));
    ws->handshake("127.0.0.1", target);
    sockets.push_back(std::move(ws));
  }
  return sockets;
}

// True once the server has closed 'ws' (messages before the close are read and dropped).
bool ClosedWithin(Socket& ws, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  beast::flat_buffer buffer;
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{beast::get_lowest_layer(ws).socket().native_handle(), POLLIN, 0};
    if (poll(&p, 1, 100) <= 0) continue;
    beast::error_code ec;
    ws.read(buffer, ec);  // a message, or the close frame / the end of the stream
    buffer.clear();
    if (ec) return true;
  }
  return false;
}

TEST(ConnectionQuotaTest, SilentSocketsAndViewersCannotLockOutAnAgent) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--agent-token", "agent-secret-1", "--viewer-token", "viewer-secret-1"});
  const unsigned short port = server.port();
  const auto created = Post(port, "/api/sessions", nlohmann::json{{"laser", LaserJson()}}.dump(),
                            {{"Authorization", "Bearer agent-secret-1"}});
  ASSERT_EQ(created.status, 201) << created.body;
  const std::string live = "/api/sessions/" + created.Json()["id"].get<std::string>() + "/live";

  asio::io_context ioc;
  // More viewers than the default quota of all WebSockets (256), all with the read-only token...
  auto viewers = OpenSockets(ioc, port, live, "viewer-secret-1", 260);
  // ...and more agent sockets than the agent quota (32), none of which ever says hello.
  auto silent = OpenSockets(ioc, port, "/api/ingest", "agent-secret-1", 40);

  WsClient agent(port, "/api/ingest", {{"Authorization", "Bearer agent-secret-1"}});
  ASSERT_TRUE(agent.open());
  agent.SendJson(Hello());
  const auto welcome = agent.ReadType("welcome", std::chrono::seconds(10));
  EXPECT_TRUE(welcome) << (agent.skipped.empty() ? "closed: " + std::string(agent.close_reason().reason.c_str())
                                                 : agent.skipped.back().dump());

  // Past the hello deadline (10 s) no silent socket is left open.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  int still_open = 0;
  for (auto& ws : silent) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (!ClosedWithin(*ws, std::max(left, std::chrono::milliseconds(1)))) ++still_open;
  }
  EXPECT_EQ(still_open, 0) << "silent agent sockets outlived the hello deadline";
  // The welcomed agent is not touched by the deadline.
  EXPECT_TRUE(SendScan(agent, 1, true));
  EXPECT_EQ(WaitForAck(agent, 1), 1);
}

}  // namespace
}  // namespace pslam::server::testing
