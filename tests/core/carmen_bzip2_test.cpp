// bzip2-compressed CARMEN logs (.clf.bz2) read like the plain file. The archives are made here
// with libbz2, from text written by the test: no binary fixtures.
#include <bzlib.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "pslam/io/carmen_reader.hpp"
#include "testing/shared_data.hpp"

namespace pslam {
namespace {

namespace fs = std::filesystem;

// ODOM and FLASER records of 180 beams, several 100 kB bzip2 blocks and read buffers long. Every
// tenth scan is written after the next ODOM, as loggers do, and every seventh has no poses, so
// its odometry comes from the ODOM records around it.
std::string SyntheticLog(int scans) {
  std::ostringstream log;
  log << "# CARMEN Logfile\nPARAM robot_frontlaser_offset 0.0 nohost 0.0\n";
  for (int i = 0; i < scans; ++i) {
    char head[160];
    const double t = 1000.0 + 0.2 * i, x = 0.05 * i, y = 0.01 * i, theta = 0.001 * i;
    std::snprintf(head, sizeof head, "ODOM %.6f %.6f %.6f 0.25 0.0 0.0 %.6f nohost %.6f\n", x, y, theta, t - 0.01, t);
    std::ostringstream scan;
    scan << "FLASER 180";
    for (int j = 0; j < 180; ++j) scan << ' ' << (100 + (i * 37 + j * 11) % 2500) / 100.0;
    char tail[160];
    if (i % 7 == 0) {
      std::snprintf(tail, sizeof tail, " %.6f nohost %.6f\n", t, t);
    } else {
      std::snprintf(tail, sizeof tail, " %.6f %.6f %.6f %.6f %.6f %.6f %.6f nohost %.6f\n", x, y, theta, x, y, theta,
                    t, t);
    }
    if (i % 10 == 3) {
      log << scan.str() << tail << head;
    } else {
      log << head << scan.str() << tail;
    }
  }
  return log.str();
}

std::string Bzip2(const std::string& text) {
  unsigned int size = static_cast<unsigned int>(text.size() + text.size() / 100 + 600);
  std::string out(size, '\0');
  const int rc = BZ2_bzBuffToBuffCompress(out.data(), &size, const_cast<char*>(text.data()),
                                          static_cast<unsigned int>(text.size()), 1, 0, 0);  // 100 kB blocks
  if (rc != BZ_OK) throw std::runtime_error("BZ2_bzBuffToBuffCompress failed: " + std::to_string(rc));
  out.resize(size);
  return out;
}

struct ReadBack {
  std::vector<LaserScan> scans;
  CarmenReadStats stats;
  double progress = 0.0;
};

ReadBack ReadLog(const fs::path& path) {
  CarmenReader reader(path.string());
  ScanStream stream(reader);
  ReadBack out;
  while (auto scan = stream.Next()) out.scans.push_back(std::move(*scan));
  out.stats = reader.stats();
  out.progress = reader.progress();
  return out;
}

void ExpectSameScans(const ReadBack& plain, const ReadBack& compressed) {
  ASSERT_EQ(compressed.scans.size(), plain.scans.size());
  for (std::size_t i = 0; i < plain.scans.size(); ++i) {
    const LaserScan &a = plain.scans[i], &b = compressed.scans[i];
    ASSERT_EQ(b.timestamp_text, a.timestamp_text) << "scan " << i;
    ASSERT_EQ(b.ranges, a.ranges) << "scan " << i;
    ASSERT_EQ(b.odometry.x, a.odometry.x) << "scan " << i;
    ASSERT_EQ(b.odometry.y, a.odometry.y) << "scan " << i;
    ASSERT_EQ(b.odometry.theta, a.odometry.theta) << "scan " << i;
  }
  EXPECT_EQ(compressed.stats.lines, plain.stats.lines);
  EXPECT_EQ(compressed.stats.odometry, plain.stats.odometry);
  EXPECT_EQ(compressed.stats.skipped_corrupt, 0u);
  EXPECT_EQ(compressed.stats.ignored_unknown, 0u);
  EXPECT_DOUBLE_EQ(compressed.progress, 1.0);
}

class CarmenBzip2Test : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           ("pslam_bzip2_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path Write(const std::string& name, const std::string& bytes) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  fs::path dir_;
};

TEST_F(CarmenBzip2Test, ReadsTheSameScansAsThePlainLog) {
  const std::string text = SyntheticLog(600);
  ASSERT_GT(text.size(), 500'000u);  // several blocks and decompression buffers
  const ReadBack plain = ReadLog(Write("log.clf", text));
  ASSERT_EQ(plain.scans.size(), 600u);
  const ReadBack compressed = ReadLog(Write("log.clf.bz2", Bzip2(text)));
  ExpectSameScans(plain, compressed);
  EXPECT_EQ(compressed.stats.scans, 600u);
}

TEST_F(CarmenBzip2Test, DetectsBzip2ByContentNotName) {
  const std::string text = SyntheticLog(20);
  const ReadBack compressed = ReadLog(Write("log.clf", Bzip2(text)));
  EXPECT_EQ(compressed.scans.size(), 20u);
}

TEST_F(CarmenBzip2Test, ReadsConcatenatedStreamsAndIgnoresTrailingBytes) {
  const std::string text = SyntheticLog(300);
  const std::size_t half = text.find('\n', text.size() / 2) + 1;
  // pbzip2 writes one stream per chunk; a cut inside a line must still join up.
  const std::string archive = Bzip2(text.substr(0, half - 40)) + Bzip2(text.substr(half - 40)) + std::string(4, '\0');
  ExpectSameScans(ReadLog(Write("plain.clf", text)), ReadLog(Write("multi.clf.bz2", archive)));
}

TEST_F(CarmenBzip2Test, TruncatedArchiveIsAnError) {
  std::string archive = Bzip2(SyntheticLog(300));
  archive.resize(archive.size() * 2 / 3);
  const fs::path path = Write("cut.clf.bz2", archive);
  try {
    ReadLog(path);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cut.clf.bz2"), std::string::npos) << e.what();
  }
}

TEST_F(CarmenBzip2Test, IntelLogSliceReadsTheSame) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  std::ifstream in(log);
  std::string text, line;
  for (int i = 0; i < 3000 && std::getline(in, line); ++i) text += line + "\n";
  const ReadBack plain = ReadLog(Write("intel.clf", text));
  ASSERT_GT(plain.scans.size(), 900u);
  ExpectSameScans(plain, ReadLog(Write("intel.clf.bz2", Bzip2(text))));
}

}  // namespace
}  // namespace pslam
