#include "link/spool.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "link/crc32.hpp"
#include "temp_dir.hpp"

namespace pslam::agent {
namespace {

using testing::TempDir;

std::vector<std::uint8_t> Payload(std::uint64_t i, std::size_t size = 100) {
  std::vector<std::uint8_t> p(size);
  for (std::size_t k = 0; k < size; ++k) p[k] = static_cast<std::uint8_t>(i * 31 + k);
  return p;
}

SpoolOptions Options(const TempDir& dir, std::uint64_t max_bytes = 1 << 20, std::uint64_t segment = 4096) {
  SpoolOptions o;
  o.directory = dir.path();
  o.max_bytes = max_bytes;
  o.segment_bytes = segment;
  return o;
}

std::vector<std::filesystem::path> Segments(const TempDir& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Crc32Test, KnownValue) {
  const std::string text = "123456789";
  EXPECT_EQ(Crc32({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}), 0xCBF43926u);
}

TEST(SpoolTest, AppendReadAcknowledge) {
  TempDir dir;
  Spool spool(Options(dir));
  for (std::uint64_t i = 1; i <= 100; ++i) EXPECT_EQ(spool.Append(Payload(i)), i);
  EXPECT_EQ(spool.stats().unacked_records, 100u);
  EXPECT_GT(Segments(dir).size(), 1u);  // 116-byte records in 4 KiB segments
  EXPECT_EQ(spool.Read(57)->payload, Payload(57));  // random access
  for (std::uint64_t i = 1; i <= 100; ++i) ASSERT_EQ(spool.Read(i)->payload, Payload(i)) << i;  // sequential
  spool.Acknowledge(80);
  EXPECT_FALSE(spool.Read(80));
  EXPECT_TRUE(spool.Read(81));
  EXPECT_EQ(spool.stats().unacked_records, 20u);
  EXPECT_LE(Segments(dir).size(), 2u);  // acknowledged segments are deleted
  spool.Acknowledge(50);  // cumulative: older acks change nothing
  EXPECT_EQ(spool.acked_seq(), 80u);
  spool.Acknowledge(100);
  EXPECT_TRUE(spool.empty_of_unacked());
}

TEST(SpoolTest, ReopenKeepsRecordsAndNumbering) {
  TempDir dir;
  {
    Spool spool(Options(dir));
    for (std::uint64_t i = 1; i <= 60; ++i) spool.Append(Payload(i));
    spool.Acknowledge(40);
  }
  Spool spool(Options(dir));
  EXPECT_EQ(spool.recovery().torn_records, 0u);
  EXPECT_EQ(spool.next_seq(), 61u);
  EXPECT_LE(spool.acked_seq(), 40u);  // acks are not persisted: the server's welcome restores them
  EXPECT_EQ(spool.Read(41)->payload, Payload(41));
  EXPECT_EQ(spool.Append(Payload(61)), 61u);
}

TEST(SpoolTest, NumberingSurvivesFullAcknowledgement) {
  TempDir dir;
  {
    Spool spool(Options(dir));
    for (std::uint64_t i = 1; i <= 200; ++i) spool.Append(Payload(i));
    spool.Acknowledge(200);
  }
  Spool spool(Options(dir));
  EXPECT_EQ(spool.next_seq(), 201u);
}

TEST(SpoolTest, DropAllKeepsNothingToResendAfterAReopen) {
  TempDir dir;
  {
    Spool spool(Options(dir));
    for (std::uint64_t i = 1; i <= 30; ++i) spool.Append(Payload(i));  // within one segment
    spool.Acknowledge(30);  // in memory only: a reopen would offer them again
    spool.DropAll();
    EXPECT_TRUE(spool.empty_of_unacked());
  }
  Spool spool(Options(dir));
  EXPECT_TRUE(spool.empty_of_unacked());
  EXPECT_EQ(spool.acked_seq(), 30u);
  EXPECT_EQ(spool.next_seq(), 31u);
  EXPECT_FALSE(spool.Read(30));
  EXPECT_EQ(Segments(dir).size(), 1u);
  EXPECT_EQ(spool.Append(Payload(31)), 31u);
}

TEST(SpoolTest, TornLastRecordIsCutNotResent) {
  TempDir dir;
  {
    Spool spool(Options(dir, 1 << 20, 1 << 20));
    for (std::uint64_t i = 1; i <= 10; ++i) spool.Append(Payload(i));
  }
  // Power cut in the middle of writing record 11: only part of it reached the disk.
  const auto segment = Segments(dir).back();
  const auto full = std::filesystem::file_size(segment);
  {
    std::ofstream out(segment, std::ios::binary | std::ios::app);
    const std::uint8_t partial[] = {100, 0, 0, 0, 0xAA, 0xBB, 0xCC, 0xDD, 11, 0, 0, 0, 0, 0, 0, 0, 1, 2, 3};
    out.write(reinterpret_cast<const char*>(partial), sizeof partial);
  }
  Spool spool(Options(dir, 1 << 20, 1 << 20));
  EXPECT_EQ(spool.recovery().torn_records, 1u);
  EXPECT_EQ(spool.recovery().records, 10u);
  EXPECT_EQ(std::filesystem::file_size(segment), full);
  EXPECT_EQ(spool.next_seq(), 11u);
  EXPECT_FALSE(spool.Read(11));
  EXPECT_EQ(spool.Append(Payload(11)), 11u);
  EXPECT_EQ(spool.Read(11)->payload, Payload(11));
}

TEST(SpoolTest, CompleteLengthButGarbageContentIsCaughtByCrc) {
  TempDir dir;
  {
    Spool spool(Options(dir, 1 << 20, 1 << 20));
    for (std::uint64_t i = 1; i <= 5; ++i) spool.Append(Payload(i));
  }
  // The last record's bytes are all there but its tail is garbage (unwritten sectors).
  const auto segment = Segments(dir).back();
  {
    std::fstream f(segment, std::ios::binary | std::ios::in | std::ios::out);
    f.seekp(static_cast<std::streamoff>(std::filesystem::file_size(segment) - 10));
    const char zeros[10] = {};
    f.write(zeros, sizeof zeros);
  }
  Spool spool(Options(dir, 1 << 20, 1 << 20));
  EXPECT_EQ(spool.recovery().torn_records, 1u);
  EXPECT_EQ(spool.next_seq(), 5u);  // record 5 dropped, 1..4 intact
  EXPECT_EQ(spool.Read(4)->payload, Payload(4));
}

TEST(SpoolTest, BoundedSizeRefusesAndCounts) {
  TempDir dir;
  Spool spool(Options(dir, 116 * 20, 116 * 5));
  std::size_t accepted = 0;
  for (std::uint64_t i = 1; i <= 30; ++i) accepted += spool.Append(Payload(i)).has_value();
  EXPECT_EQ(accepted, 20u);
  EXPECT_EQ(spool.stats().refused_full, 10u);
  EXPECT_FALSE(spool.WouldFit(100));
  // Acknowledging frees whole segments, and appending works again.
  spool.Acknowledge(10);
  EXPECT_TRUE(spool.WouldFit(100));
  EXPECT_EQ(spool.Append(Payload(21)), 21u);
}

}  // namespace
}  // namespace pslam::agent
