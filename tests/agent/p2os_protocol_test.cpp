#include "devices/p2os_protocol.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace pslam::agent::p2os {
namespace {

using Bytes = std::vector<std::uint8_t>;

// Every expected byte string below is a worked example of shared/protocols/p2os-arcos.md.
TEST(P2osProtocolTest, ChecksumMatchesWorkedExamples) {
  EXPECT_EQ(EncodeCommand(kSync0), (Bytes{0xFA, 0xFB, 0x03, 0x00, 0x00, 0x00}));
  EXPECT_EQ(EncodeCommand(kSync1), (Bytes{0xFA, 0xFB, 0x03, 0x01, 0x00, 0x01}));
  EXPECT_EQ(EncodeCommand(kEnable, 1), (Bytes{0xFA, 0xFB, 0x06, 0x04, 0x3B, 0x01, 0x00, 0x05, 0x3B}));
  EXPECT_EQ(EncodeCommand(kVel, -200), (Bytes{0xFA, 0xFB, 0x06, 0x0B, 0x1B, 0xC8, 0x00, 0xD3, 0x1B}));
  EXPECT_EQ(EncodeCommand(kVel, 200), (Bytes{0xFA, 0xFB, 0x06, 0x0B, 0x3B, 0xC8, 0x00, 0xD3, 0x3B}));
  EXPECT_EQ(EncodeCommand(kRotVel, 30), (Bytes{0xFA, 0xFB, 0x06, 0x15, 0x3B, 0x1E, 0x00, 0x33, 0x3B}));
  EXPECT_EQ(EncodeCommand(kRotVel, -30), (Bytes{0xFA, 0xFB, 0x06, 0x15, 0x1B, 0x1E, 0x00, 0x33, 0x1B}));
  EXPECT_EQ(EncodeCommand(kSonar, 0), (Bytes{0xFA, 0xFB, 0x06, 0x1C, 0x3B, 0x00, 0x00, 0x1C, 0x3B}));
  EXPECT_EQ(EncodeCommand(kHostBaud, 2), (Bytes{0xFA, 0xFB, 0x06, 0x32, 0x3B, 0x02, 0x00, 0x34, 0x3B}));
  EXPECT_EQ(EncodeCommand(kStop), (Bytes{0xFA, 0xFB, 0x03, 0x1D, 0x00, 0x1D}));
  const Bytes odd = {0x0F, 0x2B, 0x02, 0x14, 0x3C};
  EXPECT_EQ(Checksum(odd), 0x1103);  // odd length: last byte XORed, not added
}

TEST(P2osProtocolTest, DecodesCommandsBothArgumentSigns) {
  auto c = DecodeCommand(Bytes{0x0B, 0x1B, 0xC8, 0x00});
  ASSERT_TRUE(c);
  EXPECT_EQ(c->command, kVel);
  EXPECT_EQ(c->argument, -200);
  c = DecodeCommand(Bytes{0x20, 0x1B, 0xF6, 0x09});  // ARIA-style VEL2
  EXPECT_EQ(c->argument, -2550);
  EXPECT_FALSE(DecodeCommand(Bytes{0x00})->argument);
}

TEST(P2osProtocolTest, Sync2ReplyExampleParses) {
  const Bytes wire = {0xFA, 0xFB, 0x19, 0x02, 0x52, 0x6F, 0x62, 0x6F, 0x74, 0x00, 0x50, 0x69, 0x6F, 0x6E,
                      0x65, 0x65, 0x72, 0x00, 0x70, 0x33, 0x64, 0x78, 0x2D, 0x73, 0x68, 0x00, 0x3E, 0x27};
  PacketParser parser;
  parser.Push(wire, 1.0);
  const auto packet = parser.Next();
  ASSERT_TRUE(packet);
  const auto id = ParseSync2Reply(packet->payload);
  ASSERT_TRUE(id);
  EXPECT_EQ(id->name, "Robot");
  EXPECT_EQ(id->robot_class, "Pioneer");
  EXPECT_EQ(id->subclass, "p3dx-sh");
  EXPECT_EQ(EncodePacket(EncodeSync2Reply(*id)), wire);
}

const Bytes kWorkedSip = {0xFA, 0xFB, 0x28, 0x32, 0xE8, 0x03, 0xFA, 0x00, 0x00, 0x04, 0x64, 0x00, 0x64, 0x00, 0x82,
                          0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x02, 0x00, 0xDC, 0x05, 0x07, 0xFC, 0x08, 0x00,
                          0x00, 0x00, 0x00, 0x00, 0x82, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x3F, 0x9B};

TEST(P2osProtocolTest, WorkedSipDecodesAndRoundTrips) {
  PacketParser parser;
  parser.Push(kWorkedSip, 2.5);
  const auto packet = parser.Next();
  ASSERT_TRUE(packet);
  EXPECT_DOUBLE_EQ(packet->time, 2.5);
  const auto sip = DecodeSip(packet->payload);
  ASSERT_TRUE(sip);
  EXPECT_EQ(sip->x_pos, 1000);
  EXPECT_EQ(sip->y_pos, 250);
  EXPECT_EQ(sip->th_pos, 1024);
  EXPECT_EQ(sip->left_vel, 100);
  EXPECT_EQ(sip->battery_decivolts, 130);
  EXPECT_TRUE(sip->motors_enabled());
  ASSERT_EQ(sip->sonar.size(), 2u);
  EXPECT_EQ(sip->sonar[1].number, 7);
  EXPECT_EQ(sip->sonar[1].range, 2300);
  EXPECT_EQ(sip->battery_x10, 130);
  EXPECT_EQ(sip->rot_vel_decideg_s, 0);
  EXPECT_EQ(EncodePacket(EncodeSipPayload(*sip)), kWorkedSip);

  OdometryIntegrator odometry(ParamsForSubclass("p3dx-sh"));
  const OdometryReading r = odometry.Update(*sip, 2.5);
  EXPECT_NEAR(r.pose.x, 1.0, 1e-9);
  EXPECT_NEAR(r.pose.y, 0.25, 1e-9);
  EXPECT_NEAR(r.pose.theta, std::numbers::pi / 2, 1e-3);
  EXPECT_NEAR(r.translational_velocity, 0.1, 1e-9);
}

TEST(P2osProtocolTest, OldControllerUsesItsDistanceFactor) {
  EXPECT_DOUBLE_EQ(ParamsForSubclass("P3DX").dist_conv_mm, 0.485);
  EXPECT_DOUBLE_EQ(ParamsForSubclass("p3dx-sh").dist_conv_mm, 1.0);
  EXPECT_DOUBLE_EQ(ParamsForSubclass("something").dist_conv_mm, 1.0);
}

TEST(P2osProtocolTest, PositionWrapsAroundFifteenBits) {
  OdometryIntegrator odometry(RobotParams{});
  Sip sip;
  // Drive forward 300 mm per SIP across the 0x7FFF -> 0 wrap (and the 16-bit one AMRISim keeps).
  std::uint16_t raw = 0x7F00;
  double last_x = 0;
  for (int i = 0; i < 10; ++i) {
    sip.x_pos = raw;
    const auto r = odometry.Update(sip, i * 0.1);
    if (i > 0) {
      EXPECT_NEAR(r.pose.x - last_x, 0.3, 1e-9) << "step " << i;
    }
    last_x = r.pose.x;
    raw = static_cast<std::uint16_t>(raw + 300);
  }
  // Backwards too, from the last position sent.
  raw = static_cast<std::uint16_t>(raw - 300);
  for (int i = 0; i < 10; ++i) {
    raw = static_cast<std::uint16_t>(raw - 500);
    sip.x_pos = raw;
    const auto r = odometry.Update(sip, 1 + i * 0.1);
    EXPECT_NEAR(r.pose.x - last_x, -0.5, 1e-9);
    last_x = r.pose.x;
  }
}

TEST(P2osProtocolTest, HeadingIsNormalisedFromEitherRange) {
  OdometryIntegrator odometry(RobotParams{});
  Sip sip;
  sip.th_pos = 3072;  // 0..4095 convention: 270 deg = -90 deg
  EXPECT_NEAR(odometry.Update(sip, 0).pose.theta, -std::numbers::pi / 2, 2e-3);
  sip.th_pos = -1024;
  EXPECT_NEAR(odometry.Update(sip, 0.1).pose.theta, -std::numbers::pi / 2, 2e-3);
}

TEST(P2osProtocolTest, ParserSkipsNoiseAndResynchronisesAfterBadChecksum) {
  Bytes stream = {0x13, 0xFA, 0x00, 0xFB};  // noise with a false header start
  Bytes bad = kWorkedSip;
  bad[10] ^= 0x01;  // corrupt a data byte: checksum fails
  stream.insert(stream.end(), bad.begin(), bad.end());
  stream.insert(stream.end(), kWorkedSip.begin(), kWorkedSip.end());
  PacketParser parser;
  // Deliver one byte at a time: partial packets must wait, not fail.
  for (std::uint8_t b : stream) parser.Push(std::span<const std::uint8_t>(&b, 1), 0.0);
  const auto packet = parser.Next();
  ASSERT_TRUE(packet);
  EXPECT_TRUE(DecodeSip(packet->payload));
  EXPECT_FALSE(parser.Next());
  EXPECT_EQ(parser.stats().bad_checksum, 1u);
  EXPECT_EQ(parser.stats().packets, 1u);
}

TEST(P2osProtocolTest, ValidPacketHiddenInsideCorruptOneIsFound) {
  // A header whose count byte claims a long packet swallows the real SIP that follows; dropping a
  // single byte on the checksum failure finds it again.
  Bytes stream = {0xFA, 0xFB, 0x30, 0x01, 0x02};
  stream.insert(stream.end(), kWorkedSip.begin(), kWorkedSip.end());
  stream.resize(stream.size() + 10, 0x00);
  PacketParser parser;
  parser.Push(stream, 0.0);
  const auto packet = parser.Next();
  ASSERT_TRUE(packet);
  EXPECT_EQ(packet->payload[0], kSipStopped);
  EXPECT_EQ(parser.stats().bad_checksum, 1u);
}

TEST(P2osProtocolTest, StampIsArrivalOfFirstByte) {
  PacketParser parser;
  parser.Push(std::span<const std::uint8_t>(kWorkedSip.data(), 10), 5.0);
  EXPECT_FALSE(parser.Next());
  parser.Push(std::span<const std::uint8_t>(kWorkedSip.data() + 10, kWorkedSip.size() - 10), 5.04);
  const auto packet = parser.Next();
  ASSERT_TRUE(packet);
  EXPECT_DOUBLE_EQ(packet->time, 5.0);
}

}  // namespace
}  // namespace pslam::agent::p2os
