#include "devices/sick_protocol.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace pslam::agent::sick {
namespace {

using Bytes = std::vector<std::uint8_t>;

// Expected telegrams are the verified ones of shared/protocols/sick-lms200.md §4.
TEST(SickProtocolTest, CrcTraceOfStatusRequest) {
  EXPECT_EQ(Crc16(Bytes{0x02, 0x00, 0x01, 0x00, 0x31}), 0x1215);
  EXPECT_EQ(EncodeRequest(kStatus), (Bytes{0x02, 0x00, 0x01, 0x00, 0x31, 0x15, 0x12}));
}

TEST(SickProtocolTest, VerifiedHostTelegrams) {
  EXPECT_EQ(EncodeRequest(kReset), (Bytes{0x02, 0x00, 0x01, 0x00, 0x10, 0x34, 0x12}));
  EXPECT_EQ(EncodeRequest(kReadConfig), (Bytes{0x02, 0x00, 0x01, 0x00, 0x74, 0x50, 0x12}));
  const Bytes continuous = {kModeContinuous};
  EXPECT_EQ(EncodeRequest(kSwitchMode, continuous), (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x24, 0x34, 0x08}));
  const Bytes polled = {kModePolled};
  EXPECT_EQ(EncodeRequest(kSwitchMode, polled), (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x25, 0x35, 0x08}));
  const Bytes baud500k = {*BaudMode(500000)};
  EXPECT_EQ(EncodeRequest(kSwitchMode, baud500k), (Bytes{0x02, 0x00, 0x02, 0x00, 0x20, 0x48, 0x58, 0x08}));
  const Bytes variant = {0xB4, 0x00, 0x64, 0x00};
  EXPECT_EQ(EncodeRequest(kVariant, variant), (Bytes{0x02, 0x00, 0x05, 0x00, 0x3B, 0xB4, 0x00, 0x64, 0x00, 0x97, 0x49}));
  const Bytes install = {0x00, 'S', 'I', 'C', 'K', '_', 'L', 'M', 'S'};
  EXPECT_EQ(EncodeRequest(kSwitchMode, install),
            (Bytes{0x02, 0x00, 0x0A, 0x00, 0x20, 0x00, 0x53, 0x49, 0x43, 0x4B, 0x5F, 0x4C, 0x4D, 0x53, 0xBE, 0xC5}));
}

TEST(SickProtocolTest, VerifiedRepliesParseAndDecode) {
  const Bytes mode_reply = {0x02, 0x80, 0x03, 0x00, 0xA0, 0x00, 0x00, 0x06, 0x0A};
  EXPECT_EQ(EncodeReply(0xA0, Bytes{0x00}, 0x00), mode_reply);
  const Bytes scan = {0x02, 0x80, 0x0A, 0x00, 0xB0, 0x03, 0x40, 0xE8, 0x03, 0xD0, 0x07, 0xFF, 0x1F, 0x00, 0x06, 0xB1};
  TelegramParser parser(true);
  // The ACK byte before a reply and the reply itself, arriving in pieces.
  const Bytes ack = {kAck};
  parser.Push(ack, 0.0);
  parser.Push(std::span<const std::uint8_t>(mode_reply.data(), 4), 1.0);
  EXPECT_FALSE(parser.Next());
  parser.Push(std::span<const std::uint8_t>(mode_reply.data() + 4, 5), 1.01);
  parser.Push(scan, 2.0);
  auto t = parser.Next();
  ASSERT_TRUE(t);
  EXPECT_EQ(t->command, 0xA0);
  EXPECT_EQ(t->data, Bytes{0x00});
  EXPECT_DOUBLE_EQ(t->time, 1.0);
  t = parser.Next();
  ASSERT_TRUE(t);
  const auto decoded = DecodeScan(*t, 0x00);
  ASSERT_TRUE(decoded);
  ASSERT_EQ(decoded->ranges_m.size(), 3u);
  EXPECT_FLOAT_EQ(decoded->ranges_m[0], 1.0f);
  EXPECT_FLOAT_EQ(decoded->ranges_m[1], 2.0f);
  EXPECT_TRUE(std::isnan(decoded->ranges_m[2]));  // 8191: no echo
  EXPECT_EQ(parser.stats().acks, 1u);
}

TEST(SickProtocolTest, DistanceBitsFollowMeasuringModeAndUnits) {
  const std::uint16_t raw[] = {static_cast<std::uint16_t>(0xE000 | 1234), 0};  // flag bits set above 13 bits
  Telegram t;
  t.command = kScanReply;
  t.data = EncodeScanData(raw, 1);
  EXPECT_FLOAT_EQ(DecodeScan(t, 0x00)->ranges_m[0], 1.234f);  // flags masked off
  EXPECT_TRUE(std::isnan(DecodeScan(t, 0x00)->ranges_m[1]));  // 0: no return
  t.data = EncodeScanData(raw, 0);  // cm
  EXPECT_FLOAT_EQ(DecodeScan(t, 0x00)->ranges_m[0], 12.34f);
  EXPECT_NEAR(RangeFormatFor(0x05, 1).max_range_m, 32.767, 1e-9);
  const std::uint16_t wide[] = {20000};
  t.data = EncodeScanData(wide, 1);
  EXPECT_FLOAT_EQ(DecodeScan(t, 0x05)->ranges_m[0], 20.0f);
}

TEST(SickProtocolTest, CountMismatchIsRejected) {
  Telegram t;
  t.command = kScanReply;
  t.data = {0x05, 0x40, 0x01, 0x00};  // claims 5 values, carries 1
  EXPECT_FALSE(DecodeScan(t, 0));
}

TEST(SickProtocolTest, ResynchronisesAfterCorruptTelegramAndLookAlikeBytes) {
  std::vector<std::uint16_t> values(181, 1500);
  const Bytes good = EncodeReply(kScanReply, EncodeScanData(values, 1), 0x10);
  Bytes bad = good;
  bad[100] ^= 0x20;
  Bytes stream = {0x02, 0x80, 0xFF, 0x15, 0x06};  // STX + address look-alike with a bogus length
  stream.insert(stream.end(), bad.begin(), bad.end());
  stream.insert(stream.end(), good.begin(), good.end());
  TelegramParser parser(true);
  for (std::size_t i = 0; i < stream.size(); i += 7) {
    parser.Push(std::span<const std::uint8_t>(stream.data() + i, std::min<std::size_t>(7, stream.size() - i)), 0.0);
  }
  std::size_t scans = 0;
  while (auto t = parser.Next()) {
    const auto s = DecodeScan(*t, 0);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->ranges_m.size(), 181u);
    ++scans;
  }
  EXPECT_EQ(scans, 1u);
  EXPECT_GE(parser.stats().bad_crc, 1u);
}

TEST(SickProtocolTest, TelegramsReadTogetherAreStampedAsTheyCameOverTheLine) {
  std::vector<std::uint16_t> values(181, 1500);
  const Bytes scan = EncodeReply(kScanReply, EncodeScanData(values, 1), 0x10);
  Bytes two = scan;
  two.insert(two.end(), scan.begin(), scan.end());
  const double byte_seconds = LineByteSeconds(500000);
  EXPECT_DOUBLE_EQ(byte_seconds, 20e-6);

  // A busy reader got both in one read at t = 5: the first STX crossed the line 2 * size - 1
  // bytes before the last byte, the second one size - 1 bytes before.
  TelegramParser parser(true);
  parser.Push(two, 5.0, byte_seconds);
  const auto first = parser.Next();
  const auto second = parser.Next();
  ASSERT_TRUE(first && second);
  const double size = static_cast<double>(scan.size());
  EXPECT_NEAR(first->time, 5.0 - (2 * size - 1) * byte_seconds, 1e-12);
  EXPECT_NEAR(second->time, 5.0 - (size - 1) * byte_seconds, 1e-12);
  EXPECT_NEAR(second->time - first->time, size * byte_seconds, 1e-12);

  // A pseudo-terminal or a USB adapter hands bytes over faster than the line could carry them:
  // a third telegram read 1 ms later, whose start would be dated before the second one was
  // through, is stamped when the line could first have carried it.
  parser.Push(scan, 5.001, byte_seconds);
  const auto third = parser.Next();
  ASSERT_TRUE(third);
  EXPECT_NEAR(third->time, second->time + size * byte_seconds, 1e-12);

  // Without the line's byte time, both carry the read's time.
  TelegramParser undated(true);
  undated.Push(two, 5.0);
  EXPECT_DOUBLE_EQ(undated.Next()->time, 5.0);
  EXPECT_DOUBLE_EQ(undated.Next()->time, 5.0);
}

TEST(SickProtocolTest, HostDirectionParserForTheSimulator) {
  TelegramParser parser(false);
  parser.Push(EncodeRequest(kStatus), 0.0);
  const auto t = parser.Next();
  ASSERT_TRUE(t);
  EXPECT_EQ(t->command, kStatus);
  EXPECT_TRUE(t->data.empty());
}

}  // namespace
}  // namespace pslam::agent::sick
