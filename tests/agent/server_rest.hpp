#pragma once
// GET and POST of JSON resources on a pslam-server on 127.0.0.1, for tests against the real server.
#include <nlohmann/json.hpp>

#include <map>
#include <stdexcept>
#include <string>

#include "server/support/clients.hpp"

namespace pslam::agent::testing {

using server::testing::HttpResult;

// One request on a new connection; the answer whatever its status. 'token', when not empty, is
// sent as a bearer token.
inline HttpResult Request(unsigned short port, const std::string& method, const std::string& target,
                          const std::string& token = "", const std::string& json_body = "") {
  std::map<std::string, std::string> headers;
  if (!token.empty()) headers["Authorization"] = "Bearer " + token;
  return server::testing::Request(port, method, target, json_body, headers);
}

// Throws unless the answer is 200.
inline nlohmann::json GetJson(unsigned short port, const std::string& target, const std::string& token = "") {
  const auto res = Request(port, "GET", target, token);
  if (res.status != 200) throw std::runtime_error(target + ": HTTP " + std::to_string(res.status) + " " + res.body);
  return nlohmann::json::parse(res.body);
}

// POSTs 'body' (JSON); throws unless the answer is 200 or 201.
inline nlohmann::json PostJson(unsigned short port, const std::string& target, const nlohmann::json& body,
                               const std::string& token = "") {
  const auto res = Request(port, "POST", target, token, body.dump());
  if (res.status != 200 && res.status != 201) {
    throw std::runtime_error(target + ": HTTP " + std::to_string(res.status) + " " + res.body);
  }
  return nlohmann::json::parse(res.body);
}

}  // namespace pslam::agent::testing
