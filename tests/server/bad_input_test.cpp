// Bad input of every kind gets a clear error, and the server keeps serving.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sys/wait.h>
#include <limits>

#include "server/support/agent_script.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

std::string ErrorCodeAfter(WsClient& agent, const std::string& text) {
  agent.SendText(text);
  auto error = agent.ReadType("error", std::chrono::seconds(5));
  return error ? (*error)["code"].get<std::string>() + ": " + (*error)["message"].get<std::string>() : "no error";
}

TEST(BadInputTest, AgentMessagesAreRefusedOneByOneAndTheSocketStaysUsable) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--max-message-bytes", "65536"});
  WsClient agent(server.port(), "/api/ingest");
  EXPECT_EQ(ErrorCodeAfter(agent, R"({"type":"scan","seq":1})").substr(0, 11), "bad_message");  // before hello
  EXPECT_EQ(ErrorCodeAfter(agent, R"({"type":"hello","version":1,"session":"s-doesnotexist"})").substr(0, 15), "unknown_session");
  EXPECT_EQ(ErrorCodeAfter(agent, R"({"type":"hello","version":2,"laser":{}})").substr(0, 11), "bad_message");
  nlohmann::json bad_predictor = Hello();
  bad_predictor["settings"] = {{"predictor", {{"similarity_threshold", 0.9}}}};
  const std::string predictor_error = ErrorCodeAfter(agent, bad_predictor.dump());
  EXPECT_EQ(predictor_error.substr(0, 11), "bad_message");
  EXPECT_NE(predictor_error.find("similarity_threshold"), std::string::npos) << predictor_error;
  agent.SendJson(Hello());
  ASSERT_TRUE(agent.ReadType("welcome"));

  nlohmann::json scan = ScanJson(ScanInput(1, 1));
  const std::string malformed = "{\"type\":\"scan\",\"seq\":1,";
  EXPECT_EQ(ErrorCodeAfter(agent, malformed), "bad_message: malformed JSON");
  auto wrong_type = scan;
  wrong_type["seq"] = "1";
  EXPECT_NE(ErrorCodeAfter(agent, wrong_type.dump()).find("scan.seq must be an integer"), std::string::npos);
  auto negative = scan;
  negative["ranges"][3] = -1.0;
  EXPECT_NE(ErrorCodeAfter(agent, negative.dump()).find("not negative"), std::string::npos);
  auto strings = scan;
  strings["ranges"][0] = "far";
  EXPECT_NE(ErrorCodeAfter(agent, strings.dump()).find("numbers or null"), std::string::npos);
  EXPECT_EQ(ErrorCodeAfter(agent, R"({"type":"scan","seq":1,"t":NaN})"), "bad_message: malformed JSON");
  auto short_scan = scan;
  short_scan["ranges"].erase(0);
  EXPECT_NE(ErrorCodeAfter(agent, short_scan.dump()).find("181 beams"), std::string::npos);
  auto unknown = scan;
  unknown["extra"] = 1;
  EXPECT_NE(ErrorCodeAfter(agent, unknown.dump()).find("not a known field"), std::string::npos);
  EXPECT_NE(ErrorCodeAfter(agent, R"({"type":"teleport","seq":1})").find("unknown message type"), std::string::npos);
  InputRecord bad_binary = ScanInput(1, 1);
  bad_binary.ranges[5] = -2.0f;
  agent.SendBinary(EncodeBinaryScan(bad_binary));
  EXPECT_TRUE(agent.ReadType("error"));
  agent.SendBinary("PSC1 too short");
  EXPECT_TRUE(agent.ReadType("error"));
  // NaN in a binary scan is a beam without a return: accepted.
  InputRecord nan_binary = ScanInput(1, 1);
  nan_binary.ranges[7] = std::numeric_limits<float>::quiet_NaN();
  agent.SendBinary(EncodeBinaryScan(nan_binary));
  EXPECT_EQ(WaitForAck(agent, 1), 1);
  // Still in business, and nothing bad was stored.
  ASSERT_TRUE(SendScan(agent, 2, false));
  EXPECT_EQ(WaitForAck(agent, 2), 2);

  // An oversize message: too_large, then close 1009.
  agent.SendText(std::string(70000, ' '));
  auto error = agent.ReadType("error");
  ASSERT_TRUE(error);
  EXPECT_EQ((*error)["code"], "too_large");
  EXPECT_FALSE(agent.Read(std::chrono::seconds(5)));
  EXPECT_EQ(agent.close_reason().code, 1009);
  EXPECT_EQ(Get(server.port(), "/api/health").status, 200);
}

TEST(BadInputTest, RestRefusesBadRequestsWithJsonErrors) {
  TempDir dir;
  const auto web = dir.path() / "web";
  std::filesystem::create_directories(web / "assets");
  std::ofstream(web / "index.html") << "<html>viewer</html>";
  std::ofstream(web / "assets" / "app-1234.js") << "console.log(1)";
  std::ofstream(dir.path() / "secret.txt") << "secret";
  ServerProcess server(dir.path() / "data", {"--web", web.string(), "--replay-dir", web.string()});
  const unsigned short port = server.port();

  auto expect_error = [&](const HttpResult& r, int status) {
    EXPECT_EQ(r.status, status) << r.body;
    EXPECT_EQ(r.Json()["error"]["status"], status) << r.body;
  };
  expect_error(Get(port, "/api/sessions/s-0000000000000000"), 404);
  expect_error(Get(port, "/api/sessions/s-0000000000000000/map.png"), 404);
  expect_error(Get(port, "/api/sessions/..%2F..%2Fetc/stats"), 404);
  expect_error(Get(port, "/api/sessions?limit=abc"), 400);
  expect_error(Get(port, "/api/sessions?limit=-1"), 400);
  expect_error(Get(port, "/api/sessions?created_after=nan"), 400);
  expect_error(Get(port, "/api/sessions?status=active%27%3B%20DROP%20TABLE%20sessions%3B--"), 400);
  EXPECT_EQ(Get(port, "/api/sessions?name=%27%20OR%201%3D1%20--").Json()["total"], 0);
  EXPECT_EQ(Get(port, "/api/sessions?robot_id=x%27%20OR%20%271%27%3D%271").Json()["total"], 0);
  expect_error(Post(port, "/api/sessions", "{not json"), 400);
  expect_error(Post(port, "/api/sessions", R"({"laser":{"angle_min":"x"}})"), 400);
  expect_error(Post(port, "/api/sessions", nlohmann::json{{"laser", LaserJson()}, {"settings", {{"particles", -3}}}}.dump()), 400);
  expect_error(Post(port, "/api/sessions", nlohmann::json{{"laser", LaserJson()}, {"colour", "red"}}.dump()), 400);
  expect_error(Post(port, "/api/sessions", std::string(2 << 20, 'x')), 413);
  expect_error(Post(port, "/api/replays", R"({"log":"../secret.txt"})"), 400);
  expect_error(Post(port, "/api/replays", R"({"log":"/etc/passwd"})"), 400);
  expect_error(Post(port, "/api/replays", R"({"session":"s-nope"})"), 404);
  expect_error(Post(port, "/api/replays", R"({"session":"s-nope","speed":-1})"), 400);

  // Static files: served with types and caching; no way out of the web directory.
  auto index = Get(port, "/");
  EXPECT_EQ(index.status, 200);
  EXPECT_EQ(index.headers["Content-Type"], "text/html; charset=utf-8");
  EXPECT_EQ(index.headers["Cache-Control"], "no-cache");
  auto asset = Get(port, "/assets/app-1234.js");
  EXPECT_EQ(asset.headers["Content-Type"], "text/javascript; charset=utf-8");
  EXPECT_NE(asset.headers["Cache-Control"].find("immutable"), std::string::npos);
  EXPECT_EQ(Get(port, "/assets/app-1234.js", {{"If-None-Match", asset.headers["ETag"]}}).status, 304);
  EXPECT_EQ(Get(port, "/../secret.txt").status, 404);
  EXPECT_EQ(Get(port, "/%2e%2e/secret.txt").status, 404);
  EXPECT_EQ(Get(port, "/assets/..%2F..%2Fsecret.txt").status, 404);
  EXPECT_EQ(Get(port, "/map/view").body, "<html>viewer</html>");  // client-side route
  EXPECT_EQ(Get(port, "/api/health").status, 200);
}

TEST(BadInputTest, TokensAreRequiredWhenConfigured) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--agent-token", "agent-secret-1", "--viewer-token", "viewer-secret-1"});
  const unsigned short port = server.port();
  EXPECT_EQ(Get(port, "/api/sessions").status, 401);
  EXPECT_EQ(Get(port, "/api/sessions", {{"Authorization", "Bearer wrong-token"}}).status, 401);
  EXPECT_EQ(Get(port, "/api/sessions", {{"Authorization", "Bearer viewer-secret-1"}}).status, 200);
  EXPECT_EQ(Get(port, "/api/sessions?token=viewer-secret-1").status, 200);
  EXPECT_EQ(Post(port, "/api/sessions", "{}", {{"Authorization", "Bearer viewer-secret-1"}}).status, 403);
  EXPECT_EQ(Post(port, "/api/sessions", nlohmann::json{{"laser", LaserJson()}}.dump(),
                 {{"Authorization", "Bearer agent-secret-1"}}).status, 201);
  EXPECT_EQ(Get(port, "/api/health").status, 200);  // liveness probes need no token

  WsClient intruder(port, "/api/ingest", {{"Authorization", "Bearer viewer-secret-1"}});
  auto error = intruder.ReadType("error");
  ASSERT_TRUE(error);
  EXPECT_EQ((*error)["code"], "unauthorized");
  EXPECT_FALSE(intruder.Read(std::chrono::seconds(5)));
  EXPECT_EQ(intruder.close_reason().code, 1008);
  WsClient agent(port, "/api/ingest", {{"Authorization", "Bearer agent-secret-1"}});
  agent.SendJson(Hello());
  EXPECT_TRUE(agent.ReadType("welcome"));
  WsClient viewer(port, "/api/sessions/s-x/live");
  EXPECT_FALSE(viewer.open());
  const auto upgrade = Get(port, "/api/sessions/s-x/live",
                           {{"Connection", "Upgrade"}, {"Upgrade", "websocket"}, {"Sec-WebSocket-Version", "13"},
                            {"Sec-WebSocket-Key", "dGhlIHNhbXBsZSBub25jZQ=="}});
  EXPECT_EQ(upgrade.status, 401);
  // Refusals are logged as events.
  const auto events = Get(port, "/api/events", {{"Authorization", "Bearer viewer-secret-1"}}).Json()["events"];
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0]["kind"], "refused");
}

// The status of a raw request (headers and body exactly as given) on a fresh connection.
int RawStatus(unsigned short port, const std::string& request) { return RawRequest(port, request).status; }

TEST(BadInputTest, TransferCodingsOtherThanAFinalChunkedAreRefused) {
  TempDir dir;
  ServerProcess server(dir.path() / "data");
  const auto request = [](const std::string& coding) {
    return "GET /api/health HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: " + coding + "\r\n\r\n0\r\n\r\n";
  };
  // RFC 9112 6.3: without a final "chunked" the body length is unknown: 400, not "no body".
  EXPECT_EQ(RawStatus(server.port(), request("xchunked")), 400);
  EXPECT_EQ(RawStatus(server.port(), request("chunked, gzip")), 400);
  EXPECT_EQ(RawStatus(server.port(), request("gzip, chunked")), 501);  // a coding we do not decode
  EXPECT_EQ(RawStatus(server.port(), request("chunked")), 200);
  EXPECT_EQ(Get(server.port(), "/api/health").status, 200);
}

TEST(BadInputTest, RefusesToListenBeyondLoopbackWithThePlaceholderTokens) {
  TempDir dir;
  const auto log = dir.path() / "server.log";
  // 'timeout': a server that starts anyway must not outlive the test.
  const std::string command = "timeout 10 " + std::string(PSLAM_SERVER_BINARY) + " --listen 0.0.0.0:0 --data " +
                              (dir.path() / "data").string() +
                              " --agent-token change-me-agent-token-0001 --viewer-token viewer-secret-1 > /dev/null 2> " +
                              log.string();
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("placeholder token 'change-me-agent-token-0001'"), std::string::npos) << text;
  // On loopback they are harmless (tests, a first try on one machine).
  ServerProcess local(dir.path() / "local", {"--agent-token", "change-me-agent-token-0001"});
  EXPECT_EQ(Get(local.port(), "/api/health").status, 200);
}

TEST(BadInputTest, RefusesToListenBeyondLoopbackWithoutTokens) {
  const int status = std::system((std::string(PSLAM_SERVER_BINARY) + " --listen 0.0.0.0:0 --data /tmp/pslam-never-created > /dev/null 2>&1").c_str());
  EXPECT_NE(status, 0);
}

}  // namespace
}  // namespace pslam::server::testing
