#pragma once
// Test clients written with Beast: plain HTTP requests, and a WebSocket client with timeouts (for
// agents and viewers).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <utility>

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

struct HttpResult {
  int status = 0;
  std::string body;
  std::map<std::string, std::string> headers;
  nlohmann::json Json() const { return nlohmann::json::parse(body); }
};

inline HttpResult Request(unsigned short port, http::verb method, const std::string& target, const std::string& body = "",
                          const std::map<std::string, std::string>& headers = {}) {
  asio::io_context ioc;
  beast::tcp_stream stream(ioc);
  stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> req{method, target, 11};
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
  HttpResult r;
  r.status = static_cast<int>(parser.get().result_int());
  r.body = parser.get().body();
  for (const auto& field : parser.get()) r.headers[std::string(field.name_string())] = std::string(field.value());
  beast::error_code ec;
  stream.socket().shutdown(tcp::socket::shutdown_both, ec);
  return r;
}

inline HttpResult Get(unsigned short port, const std::string& target, const std::map<std::string, std::string>& h = {}) {
  return Request(port, http::verb::get, target, "", h);
}
inline HttpResult Post(unsigned short port, const std::string& target, const std::string& body,
                       const std::map<std::string, std::string>& h = {}) {
  return Request(port, http::verb::post, target, body, h);
}

struct WsMessage {
  std::string data;
  bool binary = false;
  nlohmann::json Json() const { return nlohmann::json::parse(data); }
};

class WsClient {
 public:
  // Connects and upgrades; open() is false if the server refused the upgrade.
  WsClient(unsigned short port, const std::string& target, const std::map<std::string, std::string>& headers = {})
      : ws_(ioc_) {
    beast::get_lowest_layer(ws_).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
    ws_.set_option(websocket::stream_base::decorator([headers](websocket::request_type& req) {
      for (const auto& [k, v] : headers) req.set(k, v);
    }));
    beast::error_code ec;
    ws_.handshake("127.0.0.1", target, ec);
    open_ = !ec;
    ws_.read_message_max(256u << 20);
  }
  bool open() const { return open_; }

  bool SendText(const std::string& text) { return Write(text, false); }
  bool SendBinary(const std::string& bytes) { return Write(bytes, true); }
  bool SendJson(const nlohmann::json& j) { return SendText(j.dump()); }

  // The next message, or nullopt on timeout or when the socket closed (then closed() is true).
  std::optional<WsMessage> Read(std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    if (!open_) return std::nullopt;
    bool done = false;
    beast::error_code result;
    buffer_.clear();
    ws_.async_read(buffer_, [&](beast::error_code ec, std::size_t) {
      done = true;
      result = ec;
    });
    ioc_.restart();
    ioc_.run_for(timeout);
    if (!done) {
      beast::get_lowest_layer(ws_).cancel();
      ioc_.restart();
      ioc_.run();
      open_ = false;  // a cancelled read leaves the stream unusable
      return std::nullopt;
    }
    if (result) {
      open_ = false;
      closed_ = true;
      return std::nullopt;
    }
    return WsMessage{beast::buffers_to_string(buffer_.data()), ws_.got_binary()};
  }
  // Reads until a JSON message of 'type' arrives (other messages go to 'skipped').
  std::optional<nlohmann::json> ReadType(const std::string& type, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
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
  bool closed() const { return closed_; }
  websocket::close_reason close_reason() const { return ws_.reason(); }
  void Close() {
    if (!open_) return;
    beast::error_code ec;
    ws_.close(websocket::close_code::normal, ec);
    open_ = false;
  }

  std::vector<nlohmann::json> skipped;
  int binary_skipped = 0;

 private:
  bool Write(const std::string& data, bool binary) {
    if (!open_) return false;
    ws_.binary(binary);
    beast::error_code ec;
    ws_.write(asio::buffer(data), ec);
    return !ec;
  }

  asio::io_context ioc_;
  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  bool open_ = false;
  bool closed_ = false;
};

}  // namespace pslam::server::testing
