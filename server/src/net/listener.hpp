#pragma once
// Accepts TCP connections and starts an HttpSession for each, on its own strand. Out of file
// descriptors, it backs off (50 ms doubling to 1 s) instead of retrying in a busy loop.
#include <chrono>
#include <cstdint>
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
  void BackOff(beast::error_code ec);

  net::io_context& ioc_;
  tcp::acceptor acceptor_;
  net::steady_timer backoff_timer_;  // on the acceptor's strand
  std::chrono::milliseconds backoff_{0};
  std::uint64_t failures_ = 0;  // in the current episode
  std::shared_ptr<ServerContext> context_;
};

}  // namespace pslam::server
