// The live codec's binary frames and what a tick sends (schema/ws/live.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "service/live_codec.hpp"

namespace pslam::server {
namespace {

template <typename T>
T At(const std::string& bytes, std::size_t offset) {
  T v;
  std::memcpy(&v, bytes.data() + offset, sizeof(T));
  return v;
}

LaserScan FourBeams() {
  LaserScan scan;
  scan.angle_min = -0.5;
  scan.angle_increment = 0.25;
  scan.max_range = 8.0;
  scan.ranges = {1.234f, std::numeric_limits<float>::quiet_NaN(), 8.5f, 0.01f};
  scan.sensor_offset = Pose2D(0.1, 0.0, 0.0);
  return scan;
}

TEST(LiveCodecTest, ScanFrameHoldsCentimetresThePoseAndTheSeq) {
  const Bytes frame = EncodeScanFrame(1234567890123, FourBeams(), Pose2D(1.0, 2.0, std::numbers::pi / 2));
  ASSERT_EQ(frame->size(), kScanFrameHeader + 2 * 4);
  EXPECT_EQ(frame->substr(0, 4), "PSSC");
  EXPECT_EQ(At<std::uint16_t>(*frame, 4), 4);
  EXPECT_EQ(At<std::uint8_t>(*frame, 6), kScanEncodingCentimetres);
  EXPECT_EQ(At<std::int64_t>(*frame, 8), 1234567890123);
  // The sensor 0.1 m ahead of a robot facing +y.
  EXPECT_NEAR(At<float>(*frame, 16), 1.0, 1e-6);
  EXPECT_NEAR(At<float>(*frame, 20), 2.1, 1e-6);
  EXPECT_NEAR(At<float>(*frame, 24), std::numbers::pi / 2, 1e-6);
  EXPECT_FLOAT_EQ(At<float>(*frame, 28), -0.5f);
  EXPECT_FLOAT_EQ(At<float>(*frame, 32), 0.25f);
  EXPECT_FLOAT_EQ(At<float>(*frame, 36), 8.0f);
  EXPECT_EQ(At<std::uint16_t>(*frame, 40), 123);           // 1.234 m
  EXPECT_EQ(At<std::uint16_t>(*frame, 42), kScanNoReturn);  // NaN
  EXPECT_EQ(At<std::uint16_t>(*frame, 44), kScanNoReturn);  // beyond max_range
  EXPECT_EQ(At<std::uint16_t>(*frame, 46), 1);
}

TEST(LiveCodecTest, ParticleFrameHoldsFloatsPerParticle) {
  const std::vector<Pose2D> poses = {Pose2D(1.5, -2.25, 0.125), Pose2D(3.0, 4.0, -1.0)};
  const std::vector<double> weights = {0.75};  // a missing weight is 0
  const Bytes frame = EncodeParticleFrame(poses, weights);
  ASSERT_EQ(frame->size(), kParticleFrameHeader + 2 * 16);
  EXPECT_EQ(frame->substr(0, 4), "PSPT");
  EXPECT_EQ(At<std::uint32_t>(*frame, 4), 2u);
  EXPECT_EQ(At<float>(*frame, 8), 1.5f);
  EXPECT_EQ(At<float>(*frame, 12), -2.25f);
  EXPECT_EQ(At<float>(*frame, 16), 0.125f);
  EXPECT_EQ(At<float>(*frame, 20), 0.75f);
  EXPECT_EQ(At<float>(*frame, 24 + 12), 0.0f);
}

LiveFrame Tick(std::int64_t scan_seq, bool send_stats) {
  LiveFrame f;
  f.pose = Pose2D(1.0, 2.0, 0.5);
  f.scan = std::make_shared<const LaserScan>(FourBeams());
  f.scan_seq = scan_seq;
  f.particles = {Pose2D(1.0004, 2.0, 0.12345), Pose2D(1.1, 2.1, 0.2)};
  f.weights = {0.123456, 0.876544};
  f.stats.processed_seq = scan_seq;
  f.send_stats = send_stats;
  return f;
}

TEST(LiveCodecTest, ATickSendsANewScanOnceAndStatsOnlyWhenDue) {
  LiveState state("s-1", 0.05);
  const LiveDelta first = state.Apply(Tick(5, true));
  ASSERT_TRUE(first.scan);
  EXPECT_EQ(At<std::int64_t>(*first.scan, 8), 5);
  ASSERT_TRUE(first.particles);
  EXPECT_EQ(first.particles->substr(0, 4), "PSPT");
  EXPECT_TRUE(first.stats);
  const LiveDelta same_scan = state.Apply(Tick(5, false));
  EXPECT_FALSE(same_scan.scan);       // unchanged: not sent again
  EXPECT_FALSE(same_scan.pose);       // nor are the pose and the particles
  EXPECT_FALSE(same_scan.particles);
  EXPECT_FALSE(same_scan.stats);      // not due
  // A tick that only brings due stats sends only them.
  const LiveDelta stats_only = state.Apply(Tick(5, true));
  EXPECT_TRUE(stats_only.stats);
  EXPECT_FALSE(stats_only.pose);
  EXPECT_FALSE(stats_only.particles);
  // A moved robot and moved particles are sent.
  LiveFrame moved = Tick(5, false);
  moved.pose = Pose2D(1.5, 2.0, 0.5);
  moved.particles[0].x += 0.01;
  const LiveDelta after_move = state.Apply(moved);
  EXPECT_TRUE(after_move.pose);
  EXPECT_TRUE(after_move.particles);
  // The snapshot has the current stats even when the tick did not send them, and rounded particles.
  state.Apply(Tick(6, false));
  const nlohmann::json snapshot = nlohmann::json::parse(*state.Snapshot().front().data);
  EXPECT_EQ(snapshot["stats"]["processed_seq"], 6);
  const nlohmann::json& p = snapshot["particles"][0];
  EXPECT_DOUBLE_EQ(p[0].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(p[2].get<double>(), 0.123);
  EXPECT_DOUBLE_EQ(p[3].get<double>(), 0.1235);
  EXPECT_DOUBLE_EQ(snapshot["particles"][1][3].get<double>(), 0.8765);
}

}  // namespace
}  // namespace pslam::server
