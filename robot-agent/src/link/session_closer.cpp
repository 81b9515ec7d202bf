#include "link/session_closer.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <string_view>
#include <vector>

namespace pslam::agent {
namespace {

struct Answer {
  std::optional<std::string> error;
  std::string location;  // of a 307: the node of the fleet that runs the session
};

Answer PostClose(const std::string& host, const std::string& port, const ServerLinkOptions& link,
                 const std::string& session_id, double timeout_s) {
  namespace beast = boost::beast;
  namespace http = beast::http;
  namespace net = boost::asio;
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  std::optional<std::string> error;
  http::request<http::string_body> req{http::verb::post, "/api/sessions/" + session_id + "/close", 11};
  req.set(http::field::host, host + ":" + port);
  req.set(http::field::user_agent, "pslam-agent");
  if (!link.token.empty()) req.set(http::field::authorization, "Bearer " + link.token);
  req.prepare_payload();
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  net::ip::tcp::resolver resolver(ioc);
  stream.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeout_s)));
  // One chain of asynchronous steps, so the stream's deadline covers all of them.
  resolver.async_resolve(host, port, [&](beast::error_code ec, net::ip::tcp::resolver::results_type results) {
    if (ec) return void(error = "resolve: " + ec.message());
    stream.async_connect(results, [&](beast::error_code ec, const net::ip::tcp::endpoint&) {
      if (ec) return void(error = "connect: " + ec.message());
      http::async_write(stream, req, [&](beast::error_code ec, std::size_t) {
        if (ec) return void(error = "send: " + ec.message());
        http::async_read(stream, buffer, res, [&](beast::error_code ec, std::size_t) {
          if (ec) return void(error = "read: " + ec.message());
          if (res.result_int() != 200) error = "HTTP " + std::to_string(res.result_int()) + " " + res.body().substr(0, 200);
        });
      });
    });
  });
  ioc.run();
  beast::error_code ignored;
  stream.socket().shutdown(net::ip::tcp::socket::shutdown_both, ignored);
  return {error, res.result_int() == 307 ? std::string(res[http::field::location]) : std::string()};
}

}  // namespace

std::optional<std::string> CloseServerSession(const ServerLinkOptions& link, const std::string& session_id,
                                              double timeout_s) {
  std::vector<std::string> servers = {link.host + ":" + link.port};
  servers.insert(servers.end(), link.other_servers.begin(), link.other_servers.end());
  std::optional<std::string> error;
  for (std::size_t i = 0; i < servers.size(); ++i) {
    const auto colon = servers[i].rfind(':');
    Answer answer = PostClose(servers[i].substr(0, colon), servers[i].substr(colon + 1), link, session_id, timeout_s);
    // Another node of the fleet runs the session: close it there (http://HOST:PORT/...).
    constexpr std::string_view kScheme = "http://";
    if (!answer.location.empty() && answer.location.rfind(kScheme, 0) == 0) {
      const std::string address = answer.location.substr(kScheme.size(), answer.location.find('/', kScheme.size()) - kScheme.size());
      const auto c = address.rfind(':');
      if (c != std::string::npos) answer = PostClose(address.substr(0, c), address.substr(c + 1), link, session_id, timeout_s);
    }
    if (!answer.error) return std::nullopt;
    error = answer.error;
    if (error->rfind("connect", 0) != 0 && error->rfind("resolve", 0) != 0) break;  // reached a node: its answer stands
  }
  return error;
}

}  // namespace pslam::agent
