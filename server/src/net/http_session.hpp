#pragma once
// One HTTP connection (Beast advanced_server's http_session): reads a request with a body limit
// and a timeout, hands WebSocket upgrades to the ingest or live session, and runs every other
// request on the worker pool, writing the response back on the connection's strand. One request
// at a time per connection: no pipelined backlog to bound.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "net/beast.hpp"
#include "net/server_context.hpp"

namespace pslam::server {

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket&& socket, std::shared_ptr<ServerContext> context);
  void Run();

 private:
  void Read();
  void OnRead(beast::error_code ec, std::size_t bytes);
  void Upgrade(http::request<http::string_body> req);
  void Respond(http::response<http::string_body> res);
  void OnWrite(bool keep_alive, beast::error_code ec, std::size_t bytes);
  void Close();
  void Drain();

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::shared_ptr<ServerContext> context_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::shared_ptr<http::response<http::string_body>> response_;
  std::string remote_;
  std::vector<char> drain_buffer_;
};

}  // namespace pslam::server
