#include "link/session_closer.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>

namespace pslam::agent {

std::optional<std::string> CloseServerSession(const ServerLinkOptions& link, const std::string& session_id,
                                              double timeout_s) {
  namespace beast = boost::beast;
  namespace http = beast::http;
  namespace net = boost::asio;
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  std::optional<std::string> error;
  http::request<http::string_body> req{http::verb::post, "/api/sessions/" + session_id + "/close", 11};
  req.set(http::field::host, link.host + ":" + link.port);
  req.set(http::field::user_agent, "pslam-agent");
  if (!link.token.empty()) req.set(http::field::authorization, "Bearer " + link.token);
  req.prepare_payload();
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  net::ip::tcp::resolver resolver(ioc);
  stream.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeout_s)));
  // One chain of asynchronous steps, so the stream's deadline covers all of them.
  resolver.async_resolve(link.host, link.port, [&](beast::error_code ec, net::ip::tcp::resolver::results_type results) {
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
  return error;
}

}  // namespace pslam::agent
