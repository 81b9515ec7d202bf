#include "server/support/clients.hpp"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace pslam::server::testing {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace asio = boost::asio;
using tcp = asio::ip::tcp;

namespace {

HttpResult ToResult(const http::response<http::string_body>& response) {
  HttpResult r;
  r.status = static_cast<int>(response.result_int());
  r.body = response.body();
  for (const auto& field : response) r.headers[std::string(field.name_string())] = std::string(field.value());
  return r;
}

}  // namespace

HttpResult Request(unsigned short port, const std::string& method, const std::string& target, const std::string& body,
                   const std::map<std::string, std::string>& headers) {
  asio::io_context ioc;
  beast::tcp_stream stream(ioc);
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> req;
  req.method_string(method);
  req.target(target);
  req.version(11);
  req.set(http::field::host, "127.0.0.1");
  for (const auto& [k, v] : headers) req.set(k, v);
  if (!body.empty()) {
    req.set(http::field::content_type, "application/json");
    req.body() = body;
  }
  req.prepare_payload();
  // A server may answer (413) and close before a large body is fully written: the write then fails
  // with a broken pipe, but the answer is already there to be read.
  beast::error_code write_error;
  http::write(stream, req, write_error);
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(256u << 20);
  http::read(stream, buffer, parser);
  beast::error_code ec;
  stream.socket().shutdown(tcp::socket::shutdown_both, ec);
  return ToResult(parser.get());
}

HttpResult RawRequest(unsigned short port, const std::string& bytes) {
  asio::io_context ioc;
  beast::tcp_stream stream(ioc);
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  asio::write(stream, asio::buffer(bytes));
  stream.expires_after(std::chrono::seconds(10));
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  return ToResult(res);
}

struct WsClient::Connection {
  asio::io_context ioc;
  websocket::stream<beast::tcp_stream> ws{ioc};
  beast::flat_buffer buffer;
  bool open = false;
  bool closed = false;
};

WsClient::WsClient(unsigned short port, const std::string& target, const std::map<std::string, std::string>& headers)
    : connection_(std::make_unique<Connection>()) {
  auto& ws = connection_->ws;
  beast::get_lowest_layer(ws).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  ws.set_option(websocket::stream_base::decorator([headers](websocket::request_type& req) {
    for (const auto& [k, v] : headers) req.set(k, v);
  }));
  beast::error_code ec;
  ws.handshake("127.0.0.1", target, ec);
  connection_->open = !ec;
  ws.read_message_max(256u << 20);
}

WsClient::~WsClient() = default;

bool WsClient::open() const { return connection_->open; }
bool WsClient::closed() const { return connection_->closed; }

WsCloseReason WsClient::close_reason() const {
  const auto& reason = connection_->ws.reason();
  return {static_cast<int>(reason.code), std::string(reason.reason.c_str())};
}

std::optional<WsMessage> WsClient::Read(std::chrono::milliseconds timeout) {
  Connection& c = *connection_;
  if (!c.open) return std::nullopt;
  bool done = false;
  beast::error_code result;
  c.buffer.clear();
  c.ws.async_read(c.buffer, [&](beast::error_code ec, std::size_t) {
    done = true;
    result = ec;
  });
  c.ioc.restart();
  c.ioc.run_for(timeout);
  if (!done) {
    beast::get_lowest_layer(c.ws).cancel();
    c.ioc.restart();
    c.ioc.run();
    c.open = false;  // a cancelled read leaves the stream unusable
    return std::nullopt;
  }
  if (result) {
    c.open = false;
    c.closed = true;
    return std::nullopt;
  }
  return WsMessage{beast::buffers_to_string(c.buffer.data()), c.ws.got_binary()};
}

std::optional<nlohmann::json> WsClient::ReadType(const std::string& type, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    auto m = Read(std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()));
    if (!m) return std::nullopt;
    if (m->binary) {
      ++binary_skipped;
      continue;
    }
    auto j = m->Json();
    if (j.value("type", "") == type) return j;
    skipped.push_back(j);
  }
  return std::nullopt;
}

void WsClient::Close() {
  if (!connection_->open) return;
  beast::error_code ec;
  connection_->ws.close(websocket::close_code::normal, ec);
  connection_->open = false;
}

bool WsClient::Write(const std::string& data, bool binary) {
  Connection& c = *connection_;
  if (!c.open) return false;
  c.ws.binary(binary);
  beast::error_code ec;
  c.ws.write(asio::buffer(data), ec);
  return !ec;
}

}  // namespace pslam::server::testing
