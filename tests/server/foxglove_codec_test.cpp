// The Foxglove protocol's data (schema/ws/foxglove.md): the message-data header, base64, the grid
// (cells, coarsening, colours), and which messages a session's ticks send when.
#include <gtest/gtest.h>

#include <chrono>
#include <set>
#include <string>

#include "common/base64.hpp"
#include "service/foxglove_codec.hpp"
#include "service/foxglove_state.hpp"

namespace pslam::server {
namespace {

TEST(FoxgloveCodec, MessageDataHeaderIsOpcodeSubscriptionAndTimestampLittleEndian) {
  const auto h = MessageDataHeader(0x04030201u, 0x0c0b0a0908070605ull);
  const std::array<std::uint8_t, 13> expected = {1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  EXPECT_EQ(h, expected);
}

TEST(FoxgloveCodec, Base64FollowsRfc4648) {
  EXPECT_EQ(Base64Encode(""), "");
  EXPECT_EQ(Base64Encode("f"), "Zg==");
  EXPECT_EQ(Base64Encode("fo"), "Zm8=");
  EXPECT_EQ(Base64Encode("foo"), "Zm9v");
  EXPECT_EQ(Base64Encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64Encode(std::string("\xff\x00\xfe", 3)), "/wD+");
  for (const std::string bytes : {"", "f", "fo", "foo", "foob", "fooba", "foobar", "\xff\x01\xfe"}) {
    EXPECT_EQ(Base64Decode(Base64Encode(bytes)), bytes);
  }
  EXPECT_FALSE(Base64Decode("Zg="));    // not a multiple of 4
  EXPECT_FALSE(Base64Decode("Z g=="));  // not the alphabet
  EXPECT_FALSE(Base64Decode("Zg=a"));   // padding in the middle
}

TEST(FoxgloveCodec, ChannelsAreJsonWithJsonSchemas) {
  const auto c = ChannelJson(9, "s-1", FoxgloveTopic::kMap);
  EXPECT_EQ(c["id"], 9);
  EXPECT_EQ(c["topic"], "/s-1/map");
  EXPECT_EQ(c["encoding"], "json");
  EXPECT_EQ(c["schemaName"], "foxglove.Grid");
  EXPECT_EQ(c["schemaEncoding"], "jsonschema");
  const auto schema = nlohmann::json::parse(c["schema"].get<std::string>());
  EXPECT_EQ(schema["properties"]["data"]["contentEncoding"], "base64");
  for (const FoxgloveTopic t : kFoxgloveTopics) {
    EXPECT_EQ(nlohmann::json::parse(TopicSchema(t))["type"], "object") << TopicInfo(t).suffix;
  }
}

// A grid with one free cell at (-3, 2) and one wall at (4, 5): known bounds 8 x 4 cells.
OccupancyGrid TwoCells() {
  OccupancyGrid grid(0.05);
  grid.MutableAt(-3, 2) = -4000;  // clearly free
  grid.MutableAt(4, 5) = 4000;    // clearly occupied
  return grid;
}

TEST(FoxgloveCodec, GridCoversTheKnownCellsOneByOne) {
  const auto g = nlohmann::json::parse(GridPayload(TwoCells(), 1'500'000'000'000'000'007ull));
  EXPECT_EQ(g["timestamp"]["sec"], 1'500'000'000);
  EXPECT_EQ(g["timestamp"]["nsec"], 7);
  EXPECT_EQ(g["frame_id"], "map");
  EXPECT_EQ(g["column_count"], 8);
  EXPECT_EQ(g["cell_stride"], 3);
  EXPECT_EQ(g["row_stride"], 24);
  EXPECT_DOUBLE_EQ(g["cell_size"]["x"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(g["pose"]["position"]["x"].get<double>(), -3 * 0.05);
  EXPECT_DOUBLE_EQ(g["pose"]["position"]["y"].get<double>(), 2 * 0.05);
  const std::string data = Base64Decode(g["data"].get<std::string>()).value();
  ASSERT_EQ(data.size(), 8u * 4u * 3u);
  const auto cell = [&](int c, int r) { return static_cast<std::uint8_t>(data[(r * 8 + c) * 3]); };
  const auto alpha = [&](int c, int r) { return static_cast<std::uint8_t>(data[(r * 8 + c) * 3 + 2]); };
  EXPECT_LT(cell(0, 0), 5);   // free, as a percentage
  EXPECT_GT(cell(7, 3), 95);  // the wall
  EXPECT_EQ(cell(3, 1), 255);  // unknown
  EXPECT_EQ(alpha(3, 1), 0);
  EXPECT_EQ(alpha(0, 0), 255);
  EXPECT_GT(static_cast<std::uint8_t>(data[1]), 240);        // free draws white
  EXPECT_LT(static_cast<std::uint8_t>(data[(3 * 8 + 7) * 3 + 1]), 15);  // the wall black
}

TEST(FoxgloveCodec, LargeGridsAreCoarsenedKeepingWalls) {
  // 8 x 4 cells into at most 8: blocks of 2 x 2 (4 x 2 blocks).
  const auto g = nlohmann::json::parse(GridPayload(TwoCells(), 0, 8));
  EXPECT_EQ(g["column_count"], 4);
  EXPECT_DOUBLE_EQ(g["cell_size"]["x"].get<double>(), 0.1);
  const std::string data = Base64Decode(g["data"].get<std::string>()).value();
  ASSERT_EQ(data.size(), 4u * 2u * 3u);
  const auto cell = [&](int c, int r) { return static_cast<std::uint8_t>(data[(r * 4 + c) * 3]); };
  EXPECT_LT(cell(0, 0), 5);    // the free cell's block
  EXPECT_GT(cell(3, 1), 95);   // the wall's block
  EXPECT_EQ(cell(1, 0), 255);  // nothing known
  // Into at most 7: blocks of 3 x 3, and a block holding both keeps the wall.
  const auto g3 = nlohmann::json::parse(GridPayload(TwoCells(), 0, 7));
  EXPECT_EQ(g3["column_count"], 3);
  const std::string d3 = Base64Decode(g3["data"].get<std::string>()).value();
  ASSERT_EQ(d3.size(), 3u * 2u * 3u);
  EXPECT_GT(static_cast<std::uint8_t>(d3[(1 * 3 + 2) * 3]), 95);  // cell (4, 5) is in block (2, 1)
}

TEST(FoxgloveCodec, EmptyGridIsAnEmptyMessage) {
  const auto g = nlohmann::json::parse(GridPayload(OccupancyGrid(0.05), 0));
  EXPECT_EQ(g["column_count"], 0);
  EXPECT_EQ(g["data"], "");
}

TEST(FoxgloveCodec, PosesAreDecimatedKeepingTheLatest) {
  std::vector<Pose2D> poses;
  for (int i = 0; i < 11; ++i) poses.emplace_back(i, 0.0, 0.0);
  const auto p = nlohmann::json::parse(PosesInFramePayload(poses, 0, 4));
  ASSERT_EQ(p["poses"].size(), 5u);  // every third (0, 3, 6, 9) and the latest
  EXPECT_EQ(p["poses"].back()["position"]["x"], 10.0);
}

constexpr FoxgloveState::Listening kAll = [] {
  FoxgloveState::Listening all{};
  all.fill(true);
  return all;
}();

TEST(FoxgloveCodec, PredictionGridDrawsPredictedWallsOverFreeSpace) {
  HypothesisRecord a, b;
  a.psi = 0.83;
  a.cells = {{10, 20, 0.95f}, {11, 20, 0.12f}};
  b.psi = 0.9;
  b.cells = {{11, 20, 0.95f}, {12, 21, 0.12f}};  // a wall where 'a' predicted free space
  const auto g = nlohmann::json::parse(PredictionPayload({&a, &b}, 0.05, 0));
  EXPECT_EQ(g["column_count"], 3);
  EXPECT_EQ(g["cell_stride"], 5);
  EXPECT_DOUBLE_EQ(g["pose"]["position"]["x"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(g["pose"]["position"]["y"].get<double>(), 1.0);
  const std::string data = Base64Decode(g["data"].get<std::string>()).value();
  ASSERT_EQ(data.size(), 3u * 2u * 5u);
  const auto byte = [&](int c, int r, int k) { return static_cast<std::uint8_t>(data[(r * 3 + c) * 5 + k]); };
  EXPECT_EQ(byte(0, 0, 3), 230);  // a's wall
  EXPECT_EQ(byte(0, 0, 4), 83);   // its psi
  EXPECT_EQ(byte(1, 0, 3), 230);  // b's wall wins over a's free cell
  EXPECT_EQ(byte(1, 0, 4), 90);
  EXPECT_EQ(byte(2, 1, 3), 70);   // free space: a light wash
  EXPECT_EQ(byte(2, 0, 3), 0);    // nothing predicted
}

TEST(FoxgloveState, ThePredictionOverlayHoldsOnlyPendingPredictions) {
  FoxgloveState state("s-1");
  FoxgloveState::Listening all{};
  all.fill(true);
  LiveFrame f;
  HypothesisRecord h;
  h.id = 4;
  h.cells = {{0, 0, 0.95f}};
  f.hypotheses_changed = {h};
  state.Apply(f, 1, FoxgloveState::Clock::now(), all);
  EXPECT_EQ(nlohmann::json::parse(*state.Latest(FoxgloveTopic::kPrediction)->payload)["column_count"], 1);
  h.status = "confirmed";
  f.hypotheses_changed = {h};
  state.Apply(f, 2, FoxgloveState::Clock::now(), all);
  EXPECT_EQ(nlohmann::json::parse(*state.Latest(FoxgloveTopic::kPrediction)->payload)["column_count"], 0);
}

LiveFrame Tick(int cells, double x) {
  LiveFrame f;
  auto grid = std::make_shared<OccupancyGrid>(0.05);
  for (int i = 0; i < cells; ++i) grid->MutableAt(i, 0) = 1000;
  f.map = grid;
  f.tiles.push_back({0, 0, static_cast<std::uint64_t>(cells), nullptr});
  f.pose = Pose2D(x, 0.0, 0.0);
  return f;
}

TEST(FoxgloveState, TheMapGoesOutAtMostOncePerPeriodAndTheLastChangeFollows) {
  FoxgloveState state("s-1");
  const auto t0 = FoxgloveState::Clock::now();
  const auto topics = [](const std::vector<FoxgloveMessage>& ms) {
    std::set<FoxgloveTopic> s;
    for (const auto& m : ms) s.insert(m.topic);
    return s;
  };
  auto first = topics(state.Apply(Tick(1, 0.0), 1, t0, kAll));
  EXPECT_TRUE(first.count(FoxgloveTopic::kMap));
  EXPECT_TRUE(first.count(FoxgloveTopic::kRobot));
  // 100 ms later: the pose goes, the changed map waits for its period.
  auto second = topics(state.Apply(Tick(2, 1.0), 2, t0 + std::chrono::milliseconds(100), kAll));
  EXPECT_TRUE(second.count(FoxgloveTopic::kRobot));
  EXPECT_FALSE(second.count(FoxgloveTopic::kMap));
  ASSERT_TRUE(state.NextDue().has_value());
  EXPECT_EQ(*state.NextDue(), t0 + FoxgloveState::Period(FoxgloveTopic::kMap));
  EXPECT_TRUE(state.Flush(t0 + std::chrono::milliseconds(500), kAll).empty());
  const auto flushed = state.Flush(t0 + FoxgloveState::Period(FoxgloveTopic::kMap), kAll);
  ASSERT_EQ(flushed.size(), 1u);
  EXPECT_EQ(flushed[0].topic, FoxgloveTopic::kMap);
  const auto grid = nlohmann::json::parse(*flushed[0].payload);
  EXPECT_EQ(grid["column_count"], 2);  // the second tick's map
  EXPECT_FALSE(state.NextDue().has_value());
}

TEST(FoxgloveState, OnlyListenedToTopicsAreSentButASubscriberGetsTheLatestOfAny) {
  FoxgloveState state("s-1");
  const auto t0 = FoxgloveState::Clock::now();
  FoxgloveState::Listening robot_only{};
  robot_only[static_cast<std::size_t>(FoxgloveTopic::kRobot)] = true;
  const auto sent = state.Apply(Tick(3, 2.5), 7, t0, robot_only);
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].topic, FoxgloveTopic::kRobot);
  EXPECT_FALSE(state.NextDue().has_value());
  const auto map = state.Latest(FoxgloveTopic::kMap);
  ASSERT_TRUE(map.has_value());
  EXPECT_EQ(map->ns, 7u);
  EXPECT_EQ(nlohmann::json::parse(*map->payload)["column_count"], 3);
  const auto tf = nlohmann::json::parse(*state.Latest(FoxgloveTopic::kTransform)->payload);
  EXPECT_EQ(tf["child_frame_id"], "s-1/base_link");
  EXPECT_DOUBLE_EQ(tf["translation"]["x"].get<double>(), 2.5);
  EXPECT_FALSE(state.Latest(FoxgloveTopic::kParticles).has_value());  // never had any
}

}  // namespace
}  // namespace pslam::server
