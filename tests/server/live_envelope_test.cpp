// The Redis envelope of the live stream (service/live_envelope.hpp) and the mirror a node keeps of
// a session another node runs: the owner's ticks, carried through the envelope, give the mirror
// the owner's very picture; anything malformed is an error, never a crash or a partial change.
#include <gtest/gtest.h>

#include <random>

#include "service/live_envelope.hpp"

namespace pslam::server {
namespace {

LiveTile Tile(int tx, int ty, std::uint64_t revision) {
  LiveTile t{tx, ty, revision, nullptr};
  t.cells = std::make_shared<const std::vector<std::uint8_t>>(std::vector<std::uint8_t>(40, static_cast<std::uint8_t>(revision)));
  return t;
}

HypothesisRecord Hypothesis(std::int64_t id, const std::string& status) {
  HypothesisRecord h;
  h.id = id;
  h.time = 1700000000.5;
  h.status = status;
  h.psi = 0.25;
  return h;
}

// Tick 'n' of a made-up session: tiles, pose, particles, trajectory, hypotheses, frontiers.
LiveFrame Tick(int n) {
  LiveFrame f;
  f.tiles = {Tile(n, -1, static_cast<std::uint64_t>(n)), Tile(0, 0, static_cast<std::uint64_t>(n))};
  f.pose = Pose2D(0.5 * n, -0.25 * n, 0.125 * n);
  f.scan_seq = n;
  f.particles = {Pose2D(0.5 * n, 1.25, 0.25), Pose2D(1.0, 0.5 * n, -0.5)};
  f.weights = {0.25, 0.75};
  f.trajectory_first_index = n - 1;
  TrajectoryRow row;
  row.scan_index = n - 1;
  row.seq = n;
  row.t = 100.0 + n;
  row.x = 0.5 * n;
  row.y = -0.25 * n;
  row.theta = 0.125 * n;
  f.trajectory = {row};
  if (n == 1) f.hypotheses_changed = {Hypothesis(7, "pending"), Hypothesis(8, "pending")};
  if (n == 2) f.hypotheses_changed = {Hypothesis(7, "confirmed")};
  if (n == 3) f.hypotheses_removed = {8};
  f.frontiers = {{1.0 * n, 2.0}};
  f.stats.processed_seq = n;
  return f;
}

std::string Through(const LiveDelta& d, std::uint64_t seq) { return EncodeDeltaEnvelope(42, seq, 1700000000000000, d); }

std::vector<Bytes> TileFrames(const std::vector<LiveMessage>& snapshot) {
  std::vector<Bytes> tiles;
  for (std::size_t i = 1; i < snapshot.size(); ++i) tiles.push_back(snapshot[i].data);
  return tiles;
}

void ExpectSamePicture(const LiveState& owner, const LiveState& mirror) {
  const auto a = owner.Snapshot();
  const auto b = mirror.Snapshot();
  EXPECT_EQ(nlohmann::json::parse(*b[0].data), nlohmann::json::parse(*a[0].data));
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 1; i < a.size(); ++i) EXPECT_EQ(*a[i].data, *b[i].data);
}

TEST(LiveEnvelopeTest, AMirrorFedThroughEnvelopesHoldsTheOwnersPicture) {
  LiveState owner("s-1", 0.05);
  LiveState mirror("s-1", 0.05);
  owner.Apply(Tick(1));
  // Joining late: a keyframe, then deltas.
  auto keyframe = DecodeLiveEnvelope(EncodeKeyframeEnvelope(42, 0, 1, owner.Snapshot()));
  ASSERT_TRUE(keyframe) << keyframe.error();
  EXPECT_EQ(keyframe.value().kind, LiveEnvelope::Kind::kKeyframe);
  mirror.Replace(keyframe.value().snapshot, keyframe.value().tiles);
  ExpectSamePicture(owner, mirror);
  for (int n = 2; n <= 3; ++n) {
    const LiveDelta d = owner.Apply(Tick(n));
    auto e = DecodeLiveEnvelope(Through(d, static_cast<std::uint64_t>(n)));
    ASSERT_TRUE(e) << e.error();
    EXPECT_EQ(e.value().node, 42u);
    EXPECT_EQ(e.value().seq, static_cast<std::uint64_t>(n));
    EXPECT_EQ(e.value().published_us, 1700000000000000);
    // The receiving node's viewers get the very bytes the owner's viewers get.
    ASSERT_EQ(e.value().delta.tiles.size(), d.tiles.size());
    for (std::size_t i = 0; i < d.tiles.size(); ++i) {
      EXPECT_EQ(e.value().delta.tiles[i].first, d.tiles[i].first);
      EXPECT_EQ(*e.value().delta.tiles[i].second, *d.tiles[i].second);
    }
    EXPECT_EQ(*e.value().delta.pose, *d.pose);
    EXPECT_EQ(*e.value().delta.particles, *d.particles);
    EXPECT_EQ(*TrajectoryMessage(e.value().delta.trajectory_first_index, *e.value().delta.trajectory),
              *TrajectoryMessage(d.trajectory_first_index, *d.trajectory));
    ASSERT_EQ(e.value().delta.hypotheses.size(), d.hypotheses.size());
    mirror.Absorb(e.value().delta);
    ExpectSamePicture(owner, mirror);
  }
}

TEST(LiveEnvelopeTest, AKeyframeSendsViewersOnlyWhatChanged) {
  LiveState owner("s-1", 0.05);
  LiveState mirror("s-1", 0.05);
  owner.Apply(Tick(1));
  mirror.Replace(*owner.Snapshot()[0].data, TileFrames(owner.Snapshot()));
  owner.Apply(Tick(2));
  owner.Apply(Tick(3));  // the mirror missed two ticks
  const auto snapshot = owner.Snapshot();
  const LiveDelta d = mirror.Replace(*snapshot[0].data, TileFrames(snapshot));
  ExpectSamePicture(owner, mirror);
  EXPECT_EQ(d.tiles.size(), 3u);  // (0,0) changed, (2,-1) and (3,-1) are new; (1,-1) is as it was
  ASSERT_TRUE(d.pose && d.particles && d.stats && d.exploration && d.trajectory);
  EXPECT_EQ(d.trajectory_first_index, 0);  // the whole trajectory replaces the viewer's
  EXPECT_EQ(d.trajectory->size(), 3u);
  ASSERT_EQ(d.hypotheses.size(), 2u);  // 7 updated, 8 removed
  EXPECT_NE(d.hypotheses[0].second->find("\"updated\""), std::string::npos);
  EXPECT_NE(d.hypotheses[1].second->find("\"removed\""), std::string::npos);
  // The same keyframe again changes nothing but the stats.
  const LiveDelta again = mirror.Replace(*snapshot[0].data, TileFrames(snapshot));
  EXPECT_TRUE(again.tiles.empty());
  EXPECT_FALSE(again.pose || again.particles || again.exploration || again.trajectory);
  EXPECT_TRUE(again.hypotheses.empty());
}

TEST(LiveEnvelopeTest, MalformedEnvelopesAreErrorsAndNeverCrash) {
  LiveState owner("s-1", 0.05);
  const std::string good = Through(owner.Apply(Tick(1)), 0);
  ASSERT_TRUE(DecodeLiveEnvelope(good));
  EXPECT_FALSE(DecodeLiveEnvelope(""));
  EXPECT_FALSE(DecodeLiveEnvelope("garbage"));
  EXPECT_FALSE(DecodeLiveEnvelope("XSLR" + good.substr(4)));
  std::string kind = good;
  kind[5] = 9;
  EXPECT_FALSE(DecodeLiveEnvelope(kind));
  std::string long_part = good;
  long_part[kLiveEnvelopeHeader + 1] = '\xff';  // the first part claims more bytes than there are
  EXPECT_FALSE(DecodeLiveEnvelope(long_part));
  EXPECT_FALSE(DecodeLiveEnvelope(good + std::string(kMaxLiveEnvelope, '\0')));
  EXPECT_FALSE(DecodeLiveEnvelope(EncodeKeyframeEnvelope(1, 0, 0, {})));  // no snapshot
  // Cut anywhere or with bytes flipped: an error, or an envelope the mirror takes or refuses whole.
  std::mt19937 random(5);
  for (std::size_t cut = 0; cut < good.size(); ++cut) {
    std::string bad = good.substr(0, cut);
    if (!bad.empty() && random() % 2) bad[random() % bad.size()] ^= static_cast<char>(1 + random() % 255);
    auto e = DecodeLiveEnvelope(bad);
    if (!e) continue;
    LiveState mirror("s-1", 0.05);
    try {
      mirror.Absorb(e.value().delta);
    } catch (const std::exception&) {
      EXPECT_EQ(mirror.Snapshot().size(), 1u);  // unchanged: no tile taken
    }
  }
  LiveState mirror("s-1", 0.05);
  // Well-formed JSON that lacks what the snapshot reads is refused too.
  for (const char* message : {R"({"type": "pose", "y": 1, "theta": 0})", R"({"type": "pose", "x": "1", "y": 1, "theta": 0})"}) {
    LiveDelta d;
    d.pose = MakeBytes(message);
    EXPECT_THROW(mirror.Absorb(d), std::exception) << message;
  }
  LiveDelta no_stats;
  no_stats.stats = MakeBytes(R"({"type": "stats"})");
  EXPECT_THROW(mirror.Absorb(no_stats), std::exception);
  LiveDelta no_body;
  no_body.hypotheses.emplace_back(3, MakeBytes(R"({"type": "hypothesis", "event": "added"})"));
  EXPECT_THROW(mirror.Absorb(no_body), std::exception);
  EXPECT_TRUE(nlohmann::json::parse(*mirror.Snapshot()[0].data)["pose"].is_null());
  EXPECT_THROW(mirror.Replace("{\"type\": \"snapshot\"}", {}), std::exception);
  EXPECT_THROW(mirror.Replace("not json", {}), std::exception);
  EXPECT_EQ(mirror.Snapshot().size(), 1u);
}

}  // namespace
}  // namespace pslam::server
