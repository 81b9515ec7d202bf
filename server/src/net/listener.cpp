#include "net/listener.hpp"

#include <iostream>

#include "net/http_session.hpp"

namespace pslam::server {
namespace {
constexpr std::chrono::milliseconds kFirstBackoff{50}, kMaxBackoff{1000};

// Out of descriptors or kernel memory: accepting again at once would fail again at once.
bool IsExhaustion(const beast::error_code& ec) {
  return ec == net::error::no_descriptors || ec == net::error::no_buffer_space || ec == net::error::no_memory ||
         ec == beast::error_code(ENFILE, beast::system_category());
}
}  // namespace

Listener::Listener(net::io_context& ioc, std::shared_ptr<ServerContext> context)
    : ioc_(ioc), acceptor_(net::make_strand(ioc)), backoff_timer_(acceptor_.get_executor()), context_(std::move(context)) {}

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
    self->backoff_timer_.cancel();
  });
}

void Listener::Accept() {
  acceptor_.async_accept(net::make_strand(ioc_), beast::bind_front_handler(&Listener::OnAccept, shared_from_this()));
}

void Listener::OnAccept(beast::error_code ec, tcp::socket socket) {
  if (ec == net::error::operation_aborted || !acceptor_.is_open()) return;
  if (IsExhaustion(ec)) return BackOff(ec);
  if (ec) {
    Fail(ec, "accept");  // e.g. the peer reset before we accepted: nothing to wait for
  } else {
    if (failures_ > 0) {
      std::cerr << "accept: accepting again after " << failures_ << " failed attempt(s)\n";
      failures_ = 0;
      backoff_ = std::chrono::milliseconds(0);
    }
    std::make_shared<HttpSession>(std::move(socket), context_)->Run();
  }
  Accept();
}

void Listener::BackOff(beast::error_code ec) {
  // The condition passes when connections close; until then, wait (doubling up to a second)
  // rather than spin, and say so once per episode rather than once per failure.
  if (failures_++ == 0) {
    std::cerr << "accept: " << ec.message() << "; pausing new connections (retry every " << kFirstBackoff.count()
              << " ms up to " << kMaxBackoff.count() << " ms; raise LimitNOFILE / ulimit -n if this recurs)\n";
  }
  backoff_ = backoff_.count() == 0 ? kFirstBackoff : std::min(backoff_ * 2, kMaxBackoff);
  backoff_timer_.expires_after(backoff_);
  backoff_timer_.async_wait([self = shared_from_this()](beast::error_code wait_ec) {
    if (wait_ec || !self->acceptor_.is_open()) return;
    self->Accept();
  });
}

}  // namespace pslam::server
