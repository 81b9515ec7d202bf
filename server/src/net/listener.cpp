#include "net/listener.hpp"

#include "net/http_session.hpp"

namespace pslam::server {

Listener::Listener(net::io_context& ioc, std::shared_ptr<ServerContext> context)
    : ioc_(ioc), acceptor_(net::make_strand(ioc)), context_(std::move(context)) {}

Result<std::shared_ptr<Listener>> Listener::Create(net::io_context& ioc, const tcp::endpoint& endpoint,
                                                   std::shared_ptr<ServerContext> context) {
  std::shared_ptr<Listener> listener(new Listener(ioc, std::move(context)));
  beast::error_code ec;
  auto& acceptor = listener->acceptor_;
  if (acceptor.open(endpoint.protocol(), ec); ec) return Error{"open: " + ec.message()};
  if (acceptor.set_option(net::socket_base::reuse_address(true), ec); ec) return Error{"reuse_address: " + ec.message()};
  if (acceptor.bind(endpoint, ec); ec) {
    return Error{"bind " + endpoint.address().to_string() + ":" + std::to_string(endpoint.port()) + ": " + ec.message()};
  }
  if (acceptor.listen(net::socket_base::max_listen_connections, ec); ec) return Error{"listen: " + ec.message()};
  return listener;
}

void Listener::Run() { Accept(); }

void Listener::Stop() {
  net::post(acceptor_.get_executor(), [self = shared_from_this()] {
    beast::error_code ec;
    self->acceptor_.close(ec);
  });
}

void Listener::Accept() {
  acceptor_.async_accept(net::make_strand(ioc_), beast::bind_front_handler(&Listener::OnAccept, shared_from_this()));
}

void Listener::OnAccept(beast::error_code ec, tcp::socket socket) {
  if (ec == net::error::operation_aborted || !acceptor_.is_open()) return;
  if (ec) {
    Fail(ec, "accept");  // e.g. out of file descriptors: keep accepting, the condition may pass
  } else {
    std::make_shared<HttpSession>(std::move(socket), context_)->Run();
  }
  Accept();
}

}  // namespace pslam::server
