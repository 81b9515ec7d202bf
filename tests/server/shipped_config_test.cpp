// Every config file shipped in deploy/ must parse and make a safe server: an operator copies them.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "config/server_options.hpp"

namespace pslam::server {
namespace {

const std::filesystem::path kDeploy = std::filesystem::path(PSLAM_SOURCE_DIR) / "deploy";

TEST(ShippedConfigTest, ServerConfigParsesAndListensSafely) {
  const auto parsed = ParseCommandLine({"--config", (kDeploy / "config/server.json").string()}, kDeploy);
  ASSERT_TRUE(parsed.ok()) << parsed.error();
  const ServerOptions& o = parsed.value().options;
  EXPECT_FALSE(IsLoopback(o.host));
  EXPECT_FALSE(o.agent_tokens.empty());
  EXPECT_FALSE(o.viewer_tokens.empty());
  EXPECT_TRUE(o.session_defaults.predict);
  // Its tokens are placeholders everyone can read: refused until the operator replaces them.
  const auto problem = ValidateOptions(o);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("placeholder"), std::string::npos) << *problem;
  ServerOptions replaced = o;
  replaced.agent_tokens = {"a-real-agent-secret"};
  replaced.viewer_tokens = {"a-real-viewer-secret"};
  EXPECT_EQ(ValidateOptions(replaced), std::nullopt);
}

TEST(ShippedConfigTest, AgentEnvironmentUsesAServerAgentToken) {
  const auto parsed = ParseCommandLine({"--config", (kDeploy / "config/server.json").string()}, kDeploy);
  ASSERT_TRUE(parsed.ok()) << parsed.error();
  std::ifstream env(kDeploy / "config/agent.env");
  std::string line, token;
  while (std::getline(env, line)) {
    if (line.rfind("PSLAM_AGENT_TOKEN=", 0) == 0) token = line.substr(18);
  }
  const auto& tokens = parsed.value().options.agent_tokens;
  EXPECT_NE(std::find(tokens.begin(), tokens.end(), token), tokens.end()) << "agent.env token: " << token;
}

}  // namespace
}  // namespace pslam::server
