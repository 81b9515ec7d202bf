#include "net/redis_connection.hpp"

#include <charconv>

namespace pslam::server {

Result<RedisAddress> ParseRedisUrl(const std::string& url) {
  const std::string usage = "must be a URL redis://[:PASSWORD@]HOST[:PORT]";
  if (url.rfind("redis://", 0) != 0) return Error{usage};
  std::string rest = url.substr(8);
  if (!rest.empty() && rest.back() == '/') rest.pop_back();
  if (rest.find('/') != std::string::npos) return Error{usage + " (no database: channels are global)"};
  RedisAddress a;
  if (const auto at = rest.rfind('@'); at != std::string::npos) {
    const std::string user = rest.substr(0, at);
    if (user.empty() || user[0] != ':') return Error{usage + " (only a password, no user)"};
    a.password = user.substr(1);
    rest = rest.substr(at + 1);
  }
  if (const auto colon = rest.rfind(':'); colon != std::string::npos && rest.find(']') == std::string::npos) {
    const std::string port = rest.substr(colon + 1);
    const auto [ptr, ec] = std::from_chars(port.data(), port.data() + port.size(), a.port);
    if (ec != std::errc() || ptr != port.data() + port.size() || a.port < 1 || a.port > 65535) return Error{usage + " (bad port)"};
    rest = rest.substr(0, colon);
  }
  if (rest.empty()) return Error{usage + " (no host)"};
  a.host = rest;
  return a;
}

Result<std::unique_ptr<RedisConnection>> RedisConnection::Connect(const RedisAddress& address,
                                                                   std::chrono::milliseconds timeout) {
  const timeval tv{static_cast<time_t>(timeout.count() / 1000), static_cast<suseconds_t>(timeout.count() % 1000 * 1000)};
  redisContext* c = redisConnectWithTimeout(address.host.c_str(), address.port, tv);
  if (!c) return Error{"out of memory"};
  std::unique_ptr<RedisConnection> connection(new RedisConnection(c));
  if (c->err) return Error{connection->error()};
  if (redisSetTimeout(c, tv) != REDIS_OK) return Error{connection->error()};
  if (!address.password.empty()) {
    auto* reply = static_cast<redisReply*>(redisCommand(c, "AUTH %b", address.password.data(), address.password.size()));
    if (!reply) return Error{connection->error()};
    const bool ok = reply->type != REDIS_REPLY_ERROR;
    const std::string message = ok ? "" : std::string(reply->str, reply->len);
    freeReplyObject(reply);
    if (!ok) return Error{"AUTH: " + message};
  }
  return connection;
}

}  // namespace pslam::server
