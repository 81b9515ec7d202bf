// --redis and "redis": {"url"}: the live fan-out's address, checked when the server starts.
#include <gtest/gtest.h>

#include <fstream>

#include "config/server_options.hpp"
#include "net/redis_connection.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server {
namespace {

TEST(RedisOptionsTest, UrlsNameAHostPortAndOptionalPassword) {
  auto plain = ParseRedisUrl("redis://127.0.0.1:6380");
  ASSERT_TRUE(plain) << plain.error();
  EXPECT_EQ(plain.value().host, "127.0.0.1");
  EXPECT_EQ(plain.value().port, 6380);
  EXPECT_TRUE(plain.value().password.empty());
  auto secret = ParseRedisUrl("redis://:s3cret@redis.example/");
  ASSERT_TRUE(secret) << secret.error();
  EXPECT_EQ(secret.value().host, "redis.example");
  EXPECT_EQ(secret.value().port, 6379);
  EXPECT_EQ(secret.value().password, "s3cret");
  for (const char* bad : {"127.0.0.1:6379", "redis://", "redis://host:0", "redis://host:99999", "redis://host:x",
                          "redis://user:pw@host", "redis://host:6379/2", "rediss://host"}) {
    EXPECT_FALSE(ParseRedisUrl(bad)) << bad;
  }
}

TEST(RedisOptionsTest, FlagAndConfigFileSetTheUrlAndRefuseBadOnes) {
  auto flag = ParseCommandLine({"--redis", "redis://127.0.0.1:7000"}, ".");
  ASSERT_TRUE(flag) << flag.error();
  EXPECT_EQ(flag.value().options.redis_url, "redis://127.0.0.1:7000");
  EXPECT_FALSE(ParseCommandLine({}, ".").value().options.redis_url);  // nothing changes without it
  auto bad_flag = ParseCommandLine({"--redis", "localhost:6379"}, ".");
  ASSERT_FALSE(bad_flag);
  EXPECT_NE(bad_flag.error().find("--redis must be a URL"), std::string::npos);

  testing::TempDir dir;
  auto config = [&](const std::string& json) {
    const auto file = dir.path() / "server.json";
    std::ofstream(file) << json;
    return ParseCommandLine({"--config", file.string()}, ".");
  };
  auto good = config(R"({"redis": {"url": "redis://10.0.0.5:6379"}})");
  ASSERT_TRUE(good) << good.error();
  EXPECT_EQ(good.value().options.redis_url, "redis://10.0.0.5:6379");
  auto no_url = config(R"({"redis": {}})");
  ASSERT_FALSE(no_url);
  EXPECT_NE(no_url.error().find("config.redis.url"), std::string::npos) << no_url.error();
  EXPECT_FALSE(config(R"({"redis": {"url": "http://x"}})"));
  EXPECT_FALSE(config(R"({"redis": {"url": "redis://x", "db": 1}})"));
}

}  // namespace
}  // namespace pslam::server
