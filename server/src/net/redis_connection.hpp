#pragma once
// A Redis server's address (redis://[:PASSWORD@]HOST[:PORT][/]) and one hiredis connection to it.
#include <hiredis/hiredis.h>

#include <chrono>
#include <memory>
#include <string>

#include "common/result.hpp"

namespace pslam::server {

struct RedisAddress {
  std::string host;
  int port = 6379;
  std::string password;  // empty: no AUTH
};

Result<RedisAddress> ParseRedisUrl(const std::string& url);

class RedisConnection {
 public:
  // Connects (and authenticates) within 'timeout'; replies must also come within it.
  static Result<std::unique_ptr<RedisConnection>> Connect(const RedisAddress& address, std::chrono::milliseconds timeout);
  ~RedisConnection() { redisFree(context_); }
  RedisConnection(const RedisConnection&) = delete;
  RedisConnection& operator=(const RedisConnection&) = delete;

  redisContext* get() const { return context_; }
  std::string error() const { return context_->errstr[0] ? context_->errstr : "connection lost"; }

 private:
  explicit RedisConnection(redisContext* context) : context_(context) {}
  redisContext* context_;
};

}  // namespace pslam::server
