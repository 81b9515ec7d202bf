// Sites and their map library over REST, on a real server and SQLite file: versions from a closed
// session and from imported map_server files, exported byte for byte; bad uploads refused.
#include <gtest/gtest.h>

#include "common/base64.hpp"
#include "server/support/clients.hpp"
#include "server/support/server_process.hpp"
#include "server/support/site_script.hpp"
#include "server/support/temp_dir.hpp"

namespace pslam::server::testing {
namespace {

TEST(SiteTest, MapLibraryKeepsSessionMapsAndImportsByteForByte) {
  TempDir dir;
  std::string site, session;
  const MapFiles imported = TrueRoomMap();
  {
    ServerProcess server(dir.path() / "data");
    const unsigned short port = server.port();
    site = CreateSite(port, "Building A, floor 1");
    const auto sites = Get(port, "/api/sites").Json();
    ASSERT_EQ(sites["total"], 1);
    EXPECT_EQ(sites["sites"][0]["name"], "Building A, floor 1");
    EXPECT_EQ(sites["sites"][0]["versions"], 0);
    EXPECT_TRUE(sites["sites"][0]["latest_version"].is_null());
    EXPECT_EQ(Get(port, "/api/sites/" + site + "/maps/latest").status, 404);  // no map yet

    // A session names its site; its final map becomes version 1, as its own map.pgm served it.
    session = MapRoomSession(port, site);
    EXPECT_EQ(Get(port, "/api/sessions/" + session).Json()["settings"]["site"], site);
    const auto added = Post(port, "/api/sites/" + site + "/maps", nlohmann::json{{"session_id", session}}.dump());
    ASSERT_EQ(added.status, 201) << added.body;
    EXPECT_EQ(added.Json()["version"], 1);
    EXPECT_EQ(added.Json()["source"], "session");
    EXPECT_EQ(added.Json()["session_id"], session);
    EXPECT_EQ(Get(port, "/api/sites/" + site + "/maps/1/map.pgm").body,
              Get(port, "/api/sessions/" + session + "/map.pgm").body);

    // An imported map (another tool's PGM: a comment of its own, no 'mode' key) is version 2.
    const auto second = ImportMap(port, site, imported);
    ASSERT_EQ(second.status, 201) << second.body;
    EXPECT_EQ(second.Json()["version"], 2);
    EXPECT_EQ(second.Json()["source"], "import");
    EXPECT_EQ(second.Json()["resolution"], 0.05);
  }
  // The library outlives the server: a new process on the same database serves it unchanged.
  ServerProcess server(dir.path() / "data");
  const unsigned short port = server.port();
  const auto versions = Get(port, "/api/sites/" + site + "/maps").Json()["maps"];
  ASSERT_EQ(versions.size(), 2u);
  EXPECT_EQ(versions[0]["version"], 2);  // newest first
  EXPECT_EQ(versions[1]["version"], 1);
  EXPECT_EQ(Get(port, "/api/sites/" + site).Json()["latest_version"], 2);
  EXPECT_EQ(Get(port, "/api/sites/" + site + "/maps/latest").Json()["version"], 2);
  // Export gives back exactly what was imported.
  auto pgm = Get(port, "/api/sites/" + site + "/maps/2/map.pgm");
  ASSERT_EQ(pgm.status, 200);
  EXPECT_EQ(pgm.headers["Content-Type"], "image/x-portable-graymap");
  EXPECT_EQ(pgm.body, imported.pgm);
  EXPECT_EQ(Get(port, "/api/sites/" + site + "/maps/2/map.yaml").body, imported.yaml);
  // And an export imported again is the same map once more.
  const MapFiles exported{Get(port, "/api/sites/" + site + "/maps/1/map.yaml").body,
                          Get(port, "/api/sites/" + site + "/maps/1/map.pgm").body};
  const auto third = ImportMap(port, site, exported);
  ASSERT_EQ(third.status, 201) << third.body;
  EXPECT_EQ(Get(port, "/api/sites/" + site + "/maps/3/map.pgm").body, exported.pgm);
  EXPECT_EQ(third.Json()["image"], Get(port, "/api/sites/" + site + "/maps/1").Json()["image"]);
}

TEST(SiteTest, BadRequestsAreRefusedWithReasonsAndStoreNothing) {
  TempDir dir;
  ServerProcess server(dir.path() / "data", {"--max-body-bytes", "200000"});
  const unsigned short port = server.port();
  const std::string site = CreateSite(port, "floor 2");
  const MapFiles good = TrueRoomMap();
  const auto import = [&](const nlohmann::json& body) { return Post(port, "/api/sites/" + site + "/maps", body.dump()); };
  const auto expect_refused = [&](const HttpResult& r, int status, const std::string& words) {
    EXPECT_EQ(r.status, status) << r.body;
    EXPECT_NE(r.body.find(words), std::string::npos) << r.body;
  };

  expect_refused(Post(port, "/api/sites", "{}"), 400, "site.name is required");
  expect_refused(Post(port, "/api/sites", R"({"name": "x", "floor": 2})"), 400, "floor");
  expect_refused(import({{"yaml", good.yaml}, {"pgm_base64", "not base64!"}}), 400, "pgm_base64 is not base64");
  expect_refused(import({{"yaml", good.yaml}}), 400, "are required");
  expect_refused(import({{"yaml", good.yaml}, {"pgm_base64", Base64Encode("\x89PNG\r\n\x1a\n....")}}), 400,
                 "not a PGM");
  expect_refused(import({{"yaml", good.yaml}, {"pgm_base64", Base64Encode(good.pgm.substr(0, good.pgm.size() - 100))}}),
                 400, "size mismatch");
  expect_refused(import({{"yaml", "image: a.pgm\nresolution: 0.05\n"}, {"pgm_base64", Base64Encode(good.pgm)}}), 400,
                 "missing key 'origin'");
  expect_refused(import({{"yaml", "image: a.pgm\nresolution: -1\norigin: [0, 0, 0]\n"}, {"pgm_base64", Base64Encode(good.pgm)}}),
                 400, "'resolution' must be positive");
  expect_refused(import({{"yaml", good.yaml}, {"pgm_base64", Base64Encode(good.pgm)}, {"session_id", "s-1"}}), 400,
                 "choose one source");
  // Bigger than the server takes: refused before it is parsed.
  const std::string big(300000, 'A');
  expect_refused(import({{"yaml", good.yaml}, {"pgm_base64", big}}), 413, "exceeds");
  expect_refused(import({{"session_id", "s-0123456789abcdef"}}), 404, "no session");
  expect_refused(Post(port, "/api/sites/site-nowhere/maps", nlohmann::json{{"session_id", "s-1"}}.dump()), 404, "no site");
  expect_refused(Get(port, "/api/sites/" + site + "/maps/7"), 404, "no map version 7");
  expect_refused(Get(port, "/api/sites/" + site + "/maps/seven"), 400, "version");

  // A running session's map is not final yet.
  WsClient agent(port, "/api/ingest");
  agent.SendJson(Hello("new", {{"particles", 4}, {"site", site}}));
  const std::string running = (*agent.ReadType("welcome"))["session_id"];
  expect_refused(import({{"session_id", running}}), 409, "only a closed session");
  // Sessions naming a site that does not exist, or localizing without a site or a map.
  WsClient lost(port, "/api/ingest");
  lost.SendJson(Hello("new", {{"site", "site-nowhere"}}));
  const auto error = lost.ReadType("error");
  ASSERT_TRUE(error);
  EXPECT_NE((*error)["message"].get<std::string>().find("no site 'site-nowhere'"), std::string::npos) << *error;
  const nlohmann::json laser = LaserJson();
  expect_refused(Post(port, "/api/sessions", nlohmann::json{{"laser", laser}, {"settings", {{"mode", "localize"}}}}.dump()),
                 400, "site is required in localize mode");
  expect_refused(Post(port, "/api/sessions",
                      nlohmann::json{{"laser", laser}, {"settings", {{"mode", "localize"}, {"site", site}}}}.dump()),
                 400, "has no map yet");
  expect_refused(Post(port, "/api/sessions",
                      nlohmann::json{{"laser", laser}, {"settings", {{"mode", "localise"}, {"site", site}}}}.dump()),
                 400, "settings.mode");
  expect_refused(Post(port, "/api/sessions",
                      nlohmann::json{{"laser", laser},
                                     {"settings", {{"mode", "localize"}, {"site", site}, {"localization", {{"max_particles", 0}}}}}}
                          .dump()),
                 400, "localization is invalid");

  // Nothing of it was stored.
  const auto versions = Get(port, "/api/sites/" + site + "/maps").Json()["maps"];
  EXPECT_TRUE(versions.empty()) << versions;
  EXPECT_EQ(Get(port, "/api/sites").Json()["total"], 1);
  EXPECT_EQ(Get(port, "/api/health").status, 200);
}

}  // namespace
}  // namespace pslam::server::testing
