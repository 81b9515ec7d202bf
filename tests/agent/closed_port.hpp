#pragma once
// A loopback port that refuses connections for as long as this object lives: a socket bound to it
// and never listening. A port that was bound and released instead may be handed to another test's
// server running at the same time, which then answers.
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/ip/tcp.hpp>

namespace pslam::agent::testing {

class ClosedPort {
 public:
  ClosedPort() : socket_(io_) {
    socket_.open(boost::asio::ip::tcp::v4());
    socket_.bind({boost::asio::ip::make_address("127.0.0.1"), 0});
  }
  unsigned short port() const { return socket_.local_endpoint().port(); }

 private:
  boost::asio::io_context io_;
  boost::asio::ip::tcp::socket socket_;
};

}  // namespace pslam::agent::testing
