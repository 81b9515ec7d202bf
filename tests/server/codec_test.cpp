// Pure parts of the server: the ingest codec, tile change tracking, URL query parsing, the router.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "api/query.hpp"
#include "api/router.hpp"
#include "engine/slam_pipeline.hpp"
#include "engine/tile_codec.hpp"
#include "engine/tile_tracker.hpp"
#include "service/api_error.hpp"
#include "service/ingest_codec.hpp"
#include "service/settings_codec.hpp"

namespace pslam::server {
namespace {

LaserGeometry ThreeBeams() {
  LaserGeometry l;
  l.angle_min = -0.1;
  l.angle_increment = 0.1;
  l.beams = 3;
  l.max_range = 10.0;
  return l;
}

TEST(IngestCodecTest, BinaryScansRoundTripAndNaNMeansNoReturn) {
  const LaserGeometry laser = ThreeBeams();
  InputRecord in;
  in.seq = 42;
  in.t = 1700000000.25;
  in.x = 1.5;
  in.theta = -0.5;
  in.ranges = {1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()};
  const std::string bytes = EncodeBinaryScan(in);
  ASSERT_EQ(bytes.size(), 48u + 12u);
  const auto decoded = DecodeBinaryScan({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()}, &laser);
  const auto* scan = std::get_if<InputRecord>(&decoded);
  ASSERT_TRUE(scan);
  EXPECT_EQ(scan->seq, 42);
  EXPECT_DOUBLE_EQ(scan->t, in.t);
  EXPECT_DOUBLE_EQ(scan->x, 1.5);
  EXPECT_TRUE(std::isnan(scan->ranges[1]));
  EXPECT_TRUE(std::isnan(scan->ranges[2]));  // +inf: no return
  const auto truncated = DecodeBinaryScan({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size() - 1}, &laser);
  EXPECT_TRUE(std::holds_alternative<IngestError>(truncated));
}

TEST(IngestCodecTest, JsonScansAreCheckedStrictly) {
  const LaserGeometry laser = ThreeBeams();
  const SettingsLimits limits;
  auto decode = [&](const std::string& text) { return DecodeTextMessage(text, &laser, limits); };
  const auto ok = decode(R"({"type":"scan","seq":3,"t":1.5,"odom":{"x":0,"y":0,"theta":0},"ranges":[1.0,null,2.5]})");
  ASSERT_TRUE(std::holds_alternative<InputRecord>(ok));
  EXPECT_TRUE(std::isnan(std::get<InputRecord>(ok).ranges[1]));
  for (const char* bad : {R"({"type":"scan","seq":0,"t":1,"odom":{"x":0,"y":0,"theta":0},"ranges":[1,1,1]})",
                          R"({"type":"scan","seq":1.5,"t":1,"odom":{"x":0,"y":0,"theta":0},"ranges":[1,1,1]})",
                          R"({"type":"scan","seq":1,"t":1,"odom":{"x":0,"y":0},"ranges":[1,1,1]})",
                          R"({"type":"scan","seq":1,"t":1,"odom":{"x":0,"y":0,"theta":0},"ranges":[1,-1,1]})",
                          R"({"type":"scan","seq":1,"t":1e999,"odom":{"x":0,"y":0,"theta":0},"ranges":[1,1,1]})",
                          R"({"type":"odom","seq":1,"t":1,"x":0,"y":0,"theta":"0"})", R"([1,2,3])", R"({"seq":1})",
                          R"({"type":"hello","version":1})"}) {
    const auto result = decode(bad);
    ASSERT_TRUE(std::holds_alternative<IngestError>(result)) << bad;
    EXPECT_EQ(std::get<IngestError>(result).code, "bad_message") << bad;
  }
  // Before the hello only a hello is accepted, and a new session needs its laser.
  EXPECT_TRUE(std::holds_alternative<IngestError>(DecodeTextMessage(R"({"type":"hello","version":1})", nullptr, limits)));
  const auto hello = DecodeTextMessage(
      R"({"type":"hello","version":1,"session":"s-1","settings":{"particles":5}})", nullptr, limits);
  ASSERT_TRUE(std::holds_alternative<HelloMessage>(hello));
  EXPECT_EQ(std::get<HelloMessage>(hello).session, "s-1");
}

TEST(SettingsCodecTest, DegeneracyGuardReachesBothScanMatchesAndIsBounded) {
  const SettingsLimits limits;
  const SessionSettings s = ParseSessionSettings(nlohmann::json{{"degenerate_ratio", 0.3}}, {}, limits);
  EXPECT_DOUBLE_EQ(s.degenerate_ratio, 0.3);
  const PSlamOptions options = ToPSlamOptions(s);
  EXPECT_DOUBLE_EQ(options.filter.tracking_match.degenerate_ratio, 0.3);
  EXPECT_DOUBLE_EQ(options.filter.particle_match.degenerate_ratio, 0.3);
  // Stored sessions come back with the same settings.
  EXPECT_DOUBLE_EQ(ParseSessionSettings(SessionSettingsToJson(s), {}, limits).degenerate_ratio, 0.3);
  // On by default, as in the core (pslam run); 0 turns it off.
  EXPECT_DOUBLE_EQ(ToPSlamOptions(SessionSettings{}).filter.tracking_match.degenerate_ratio,
                   RbpfOptions{}.tracking_match.degenerate_ratio);
  EXPECT_GT(SessionSettings{}.degenerate_ratio, 0.0);
  EXPECT_DOUBLE_EQ(ParseSessionSettings(nlohmann::json{{"degenerate_ratio", 0}}, {}, limits).degenerate_ratio, 0.0);
  EXPECT_ANY_THROW(ParseSessionSettings(nlohmann::json{{"degenerate_ratio", 1.0}}, {}, limits));
  EXPECT_ANY_THROW(ParseSessionSettings(nlohmann::json{{"degenerate_ratio", "high"}}, {}, limits));
}

TEST(SettingsCodecTest, OdometryPriorReachesBothScanMatchesAndIsBounded) {
  const SettingsLimits limits;
  const SessionSettings s = ParseSessionSettings(nlohmann::json{{"odometry_prior", 30}}, {}, limits);
  const PSlamOptions options = ToPSlamOptions(s);
  EXPECT_DOUBLE_EQ(options.filter.tracking_match.prior_translation_weight, 30.0);
  EXPECT_DOUBLE_EQ(options.filter.particle_match.prior_translation_weight, 30.0);
  EXPECT_DOUBLE_EQ(ParseSessionSettings(SessionSettingsToJson(s), {}, limits).odometry_prior, 30.0);
  // Off by default, as in the core (pslam run).
  EXPECT_DOUBLE_EQ(ToPSlamOptions(SessionSettings{}).filter.tracking_match.prior_translation_weight, 0.0);
  EXPECT_ANY_THROW(ParseSessionSettings(nlohmann::json{{"odometry_prior", -1}}, {}, limits));
  EXPECT_ANY_THROW(ParseSessionSettings(nlohmann::json{{"odometry_prior", 1e6}}, {}, limits));
  EXPECT_ANY_THROW(ParseSessionSettings(nlohmann::json{{"odometry_prior", "strong"}}, {}, limits));
}

TEST(SettingsCodecTest, HitOffsetsReachBothScanMatches) {
  const SettingsLimits limits;
  EXPECT_TRUE(ToPSlamOptions(SessionSettings{}).filter.particle_match.hit_offsets);  // as in the core
  const SessionSettings s = ParseSessionSettings(nlohmann::json{{"hit_offsets", false}}, {}, limits);
  const PSlamOptions options = ToPSlamOptions(s);
  EXPECT_FALSE(options.filter.tracking_match.hit_offsets);
  EXPECT_FALSE(options.filter.particle_match.hit_offsets);
  EXPECT_FALSE(ParseSessionSettings(SessionSettingsToJson(s), {}, limits).hit_offsets);
  EXPECT_ANY_THROW(ParseSessionSettings(nlohmann::json{{"hit_offsets", "no"}}, {}, limits));
}

TEST(TileTrackerTest, ReportsWrittenTilesOnlyAndSurvivesCopies) {
  OccupancyGrid grid(0.05);
  grid.AddLogOdds(1, 1, 100, -2000, 2000);
  grid.AddLogOdds(200, 5, 100, -2000, 2000);
  TileTracker tracker;
  EXPECT_EQ(tracker.Changed(grid).size(), 2u);  // first look: everything
  EXPECT_TRUE(tracker.Changed(grid).empty());
  grid.AddLogOdds(2, 2, 50, -2000, 2000);
  const auto changed = tracker.Changed(grid);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0], Eigen::Vector2i(0, 0));
  OccupancyGrid other(0.05);  // the best particle switched to one that never saw tile (3, 0)
  other.AddLogOdds(1, 1, 100, -2000, 2000);
  EXPECT_EQ(tracker.Changed(other).size(), 2u);  // (0, 0) differs, (3, 0) vanished
}

TEST(TileCodecTest, StoredTilesReloadExactly) {
  OccupancyGrid grid(0.05);
  grid.AddLogOdds(-70, 3, 900, -2000, 2000);
  grid.AddLogOdds(-69, 3, -400, -2000, 2000);
  const OccupancyGrid::Tile* tile = grid.TileAt(-70 >> 6, 0);
  ASSERT_TRUE(tile);
  TileRow row{-70 >> 6, 0, 64, 1, EncodeStoredTile(tile)};
  const OccupancyGrid reloaded = GridFromTiles({row}, 0.05);
  EXPECT_EQ(reloaded.At(-70, 3), grid.At(-70, 3));
  EXPECT_EQ(reloaded.At(-69, 3), grid.At(-69, 3));
  EXPECT_FALSE(reloaded.IsKnown(-68, 3));
  EXPECT_TRUE(GridFromTiles({{0, 0, 64, 1, {1, 2, 3}}}, 0.05).KnownBounds().empty());  // corrupt: skipped
}

TEST(QueryTest, DecodesTargetsAndRejectsBadValues) {
  const auto t = ParseTarget("/api/sessions?name=a%20b+c&limit=5&flag");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->path, "/api/sessions");
  EXPECT_EQ(t->query.at("name"), "a b c");
  EXPECT_EQ(*QueryInteger(t->query, "limit", 1, 10), 5);
  EXPECT_THROW(QueryInteger(t->query, "limit", 6, 10), ApiError);
  EXPECT_THROW(QueryNumber({{"x", "1.5abc"}}, "x"), ApiError);
  EXPECT_THROW(QueryNumber({{"x", "inf"}}, "x"), ApiError);
  EXPECT_FALSE(ParseTarget("/a%2"));
  EXPECT_FALSE(ParseTarget("/a%00b"));
  EXPECT_FALSE(ParseTarget("relative"));
}

TEST(RouterTest, MapsMethodsAccessAndErrorsToStatuses) {
  Router router;
  router.Add("GET", "/api/things/{id}", Access::kRead, [](const ApiRequest& r) {
    if (r.Param("id") == "boom") throw std::runtime_error("secret detail");
    if (r.Param("id") == "missing") throw ApiError::NotFound("no thing");
    return JsonResponse(200, "{\"id\":\"" + r.Param("id") + "\"}");
  });
  router.Add("POST", "/api/things", Access::kWrite, [](const ApiRequest&) { return JsonResponse(201, "{}"); });
  auto call = [&](const std::string& method, const std::string& path, Access access) {
    ApiRequest r;
    r.method = method;
    r.path = path;
    r.access = access;
    return router.Handle(r);
  };
  EXPECT_EQ(call("GET", "/api/things/7", Access::kRead).status, 200);
  EXPECT_EQ(call("HEAD", "/api/things/7", Access::kRead).status, 200);
  EXPECT_EQ(call("GET", "/api/things/missing", Access::kRead).status, 404);
  const ApiResponse internal = call("GET", "/api/things/boom", Access::kRead);
  EXPECT_EQ(internal.status, 500);
  EXPECT_EQ(internal.body.find("secret"), std::string::npos);
  EXPECT_EQ(call("GET", "/api/things/7", Access::kNone).status, 401);
  EXPECT_EQ(call("POST", "/api/things", Access::kRead).status, 403);
  EXPECT_EQ(call("DELETE", "/api/things/7", Access::kWrite).status, 405);
  EXPECT_EQ(call("GET", "/api/other", Access::kWrite).status, 404);
}

TEST(AccessTest, TokensGrantReadOrWrite) {
  EXPECT_EQ(TokenAuth({}, {}).Check(""), Access::kWrite);  // no tokens configured: loopback, open
  const TokenAuth auth({"agent-token"}, {"viewer-token"});
  EXPECT_EQ(auth.Check(""), Access::kNone);
  EXPECT_EQ(auth.Check("agent-tokeN"), Access::kNone);
  EXPECT_EQ(auth.Check("agent-token"), Access::kWrite);
  EXPECT_EQ(auth.Check("viewer-token"), Access::kRead);
}

}  // namespace
}  // namespace pslam::server
