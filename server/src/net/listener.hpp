#pragma once
// Accepts TCP connections and starts an HttpSession for each, on its own strand.
#include <memory>

#include "common/result.hpp"
#include "net/beast.hpp"
#include "net/server_context.hpp"

namespace pslam::server {

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  // Opens, binds and listens on 'endpoint'; an error (address in use, permission) is returned, not
  // reported from a half-built object.
  static Result<std::shared_ptr<Listener>> Create(net::io_context& ioc, const tcp::endpoint& endpoint,
                                                  std::shared_ptr<ServerContext> context);
  void Run();
  // Stops accepting; open connections are not touched.
  void Stop();
  tcp::endpoint local_endpoint() const { return acceptor_.local_endpoint(); }

 private:
  Listener(net::io_context& ioc, std::shared_ptr<ServerContext> context);
  void Accept();
  void OnAccept(beast::error_code ec, tcp::socket socket);

  net::io_context& ioc_;
  tcp::acceptor acceptor_;
  std::shared_ptr<ServerContext> context_;
};

}  // namespace pslam::server
