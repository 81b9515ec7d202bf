#pragma once
// Namespace aliases for Boost.Beast and Asio (as Beast's chat-multi example does); nothing else.
// Boost 1.74 asio/awaitable.hpp uses std::exchange without including <utility> under C++20.
#include <utility>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace pslam::server {

namespace beast = boost::beast;
namespace http = boost::beast::http;
namespace websocket = boost::beast::websocket;
namespace net = boost::asio;
using tcp = boost::asio::ip::tcp;

// Logs an asynchronous operation's failure, except the ones that only mean "the peer or we closed".
void Fail(beast::error_code ec, const char* what);

}  // namespace pslam::server
