#pragma once
// GET and POST of JSON resources on a pslam-server on 127.0.0.1, for tests against the real server.
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace pslam::agent::testing {

// One request on a new connection; the answer whatever its status. 'token', when not empty, is
// sent as a bearer token.
inline boost::beast::http::response<boost::beast::http::string_body> Request(
    unsigned short port, boost::beast::http::verb verb, const std::string& target, const std::string& token = "",
    const std::string& json_body = "") {
  namespace beast = boost::beast;
  namespace http = beast::http;
  boost::asio::io_context ioc;
  beast::tcp_stream stream(ioc);
  stream.connect(boost::asio::ip::tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), port));
  http::request<http::string_body> req{verb, target, 11};
  req.set(http::field::host, "127.0.0.1");
  if (!token.empty()) req.set(http::field::authorization, "Bearer " + token);
  if (!json_body.empty()) req.set(http::field::content_type, "application/json");
  req.body() = json_body;
  req.prepare_payload();
  http::write(stream, req);
  beast::flat_buffer buffer;
  http::response<http::string_body> res;
  http::read(stream, buffer, res);
  return res;
}

// Throws unless the answer is 200.
inline nlohmann::json GetJson(unsigned short port, const std::string& target, const std::string& token = "") {
  const auto res = Request(port, boost::beast::http::verb::get, target, token);
  if (res.result_int() != 200) throw std::runtime_error(target + ": HTTP " + std::to_string(res.result_int()) + " " + res.body());
  return nlohmann::json::parse(res.body());
}

// POSTs 'body' (JSON); throws unless the answer is 200 or 201.
inline nlohmann::json PostJson(unsigned short port, const std::string& target, const nlohmann::json& body,
                               const std::string& token = "") {
  const auto res = Request(port, boost::beast::http::verb::post, target, token, body.dump());
  if (res.result_int() != 200 && res.result_int() != 201) {
    throw std::runtime_error(target + ": HTTP " + std::to_string(res.result_int()) + " " + res.body());
  }
  return nlohmann::json::parse(res.body());
}

}  // namespace pslam::agent::testing
