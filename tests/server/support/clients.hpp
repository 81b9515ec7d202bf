#pragma once
// Test clients: plain HTTP requests, and a WebSocket client with timeouts (for agents and viewers).
// Beast stays in clients.cpp, compiled once, so that the many tests using them compile quickly.
#include <nlohmann/json.hpp>

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pslam::server::testing {

struct HttpResult {
  int status = 0;
  std::string body;
  std::map<std::string, std::string> headers;
  nlohmann::json Json() const { return nlohmann::json::parse(body); }
};

// One request on a new connection to 127.0.0.1:'port'; 'method' as on the wire ("GET", "DELETE").
HttpResult Request(unsigned short port, const std::string& method, const std::string& target, const std::string& body = "",
                   const std::map<std::string, std::string>& headers = {});

// 'bytes' sent exactly as given (request line, headers and body) on a new connection; the answer.
HttpResult RawRequest(unsigned short port, const std::string& bytes);

inline HttpResult Get(unsigned short port, const std::string& target, const std::map<std::string, std::string>& h = {}) {
  return Request(port, "GET", target, "", h);
}
inline HttpResult Post(unsigned short port, const std::string& target, const std::string& body,
                       const std::map<std::string, std::string>& h = {}) {
  return Request(port, "POST", target, body, h);
}

struct WsMessage {
  std::string data;
  bool binary = false;
  nlohmann::json Json() const { return nlohmann::json::parse(data); }
};

struct WsCloseReason {
  int code = 0;
  std::string reason;
};

class WsClient {
 public:
  // Connects and upgrades; open() is false if the server refused the upgrade.
  WsClient(unsigned short port, const std::string& target, const std::map<std::string, std::string>& headers = {});
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  bool open() const;
  bool SendText(const std::string& text) { return Write(text, false); }
  bool SendBinary(const std::string& bytes) { return Write(bytes, true); }
  bool SendJson(const nlohmann::json& j) { return SendText(j.dump()); }

  // The next message, or nullopt on timeout or when the socket closed (then closed() is true).
  std::optional<WsMessage> Read(std::chrono::milliseconds timeout = std::chrono::seconds(10));
  // Reads until a JSON message of 'type' arrives (other messages go to 'skipped').
  std::optional<nlohmann::json> ReadType(const std::string& type, std::chrono::milliseconds timeout = std::chrono::seconds(10));
  bool closed() const;
  WsCloseReason close_reason() const;
  void Close();

  std::vector<nlohmann::json> skipped;
  int binary_skipped = 0;

 private:
  bool Write(const std::string& data, bool binary);

  struct Connection;
  std::unique_ptr<Connection> connection_;
};

}  // namespace pslam::server::testing
