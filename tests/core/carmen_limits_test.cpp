// Hostile CARMEN logs: a line too long to buffer, and poses no robot could have. They end in a
// clear error that names the file and line (or the scan), never in an abort or gigabytes of RAM.
#include <bzlib.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "pslam/experiment/log_run.hpp"
#include "pslam/io/carmen_reader.hpp"

namespace pslam {
namespace {

namespace fs = std::filesystem;

// 180-beam FLASER records 0.2 s apart along x; with a 'scale', the robot starts at x = scale and
// moves 0.05 * scale per scan.
std::string Log(int scans, double scale = 0.0) {
  std::ostringstream log;
  for (int i = 0; i < scans; ++i) {
    const double t = 1000.0 + 0.2 * i, x = scale == 0.0 ? 0.05 * i : scale * (1.0 + 0.05 * i);
    log.precision(17);
    log << "FLASER 180";
    for (int j = 0; j < 180; ++j) log << ' ' << 1.0 + (j % 40) / 10.0;
    log << ' ' << x << " 0 0 " << x << " 0 0 " << t << " nohost " << t << "\n";
  }
  return log.str();
}

const std::string kLongLine = "FLASER 3 " + std::string(3u << 20, '1') + "\n";  // 3 MiB of one number

class CarmenLimitsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pslam-carmen-limits-" + std::to_string(::getpid()));
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

std::string Bzip2(const std::string& text) {
  unsigned int size = static_cast<unsigned int>(text.size() + text.size() / 100 + 600);
  std::string out(size, '\0');
  const int rc = BZ2_bzBuffToBuffCompress(out.data(), &size, const_cast<char*>(text.data()),
                                          static_cast<unsigned int>(text.size()), 9, 0, 0);
  if (rc != BZ_OK) throw std::runtime_error("BZ2_bzBuffToBuffCompress failed: " + std::to_string(rc));
  out.resize(size);
  return out;
}

void ExpectLongLineSkipped(CarmenReader& reader, const std::string& name) {
  ScanStream scans(reader);
  int n = 0;
  while (scans.Next()) ++n;
  EXPECT_EQ(n, 4);  // the lines around the long one
  ASSERT_EQ(reader.stats().skipped_corrupt, 1u);
  ASSERT_FALSE(reader.stats().first_errors.empty());
  EXPECT_EQ(reader.stats().first_errors[0], name + ":3: line longer than 1048576 bytes; skipped");
}

TEST_F(CarmenLimitsTest, LineLongerThanTheLimitIsACorruptLineWithItsNumber) {
  const std::string log = Log(2) + kLongLine + Log(2);
  std::istringstream in(log);
  CarmenReader reader(in, "long.log");
  ExpectLongLineSkipped(reader, "long.log");

  std::istringstream strict_in(log);
  CarmenReader strict(strict_in, "long.log", {.strict = true});
  try {
    while (strict.Next()) {
    }
    FAIL() << "a strict reader accepted the long line";
  } catch (const CarmenParseError& e) {
    EXPECT_NE(std::string(e.what()).find("long.log:3: line longer than"), std::string::npos) << e.what();
  }
}

TEST_F(CarmenLimitsTest, LineLongerThanTheLimitInABzip2Log) {
  const fs::path path = Write("long.clf.bz2", Bzip2(Log(2) + kLongLine + Log(2)));
  CarmenReader reader(path.string());
  ExpectLongLineSkipped(reader, path.string());
}

TEST_F(CarmenLimitsTest, LineLongerThanTheLimitAtTheEndWithoutNewline) {
  const std::string log = Log(4) + "FLASER 3 " + std::string(2u << 20, '2');
  std::istringstream in(log);
  CarmenReader reader(in, "tail.log");
  ScanStream scans(reader);
  int n = 0;
  while (scans.Next()) ++n;
  EXPECT_EQ(n, 4);
  EXPECT_EQ(reader.stats().skipped_corrupt, 1u);
}

TEST_F(CarmenLimitsTest, PosesOfATrillionMetresAreCorruptLines) {
  std::istringstream in(Log(3, 1e12) + Log(1));
  CarmenReader reader(in, "far.log");
  ScanStream scans(reader);
  int n = 0;
  while (scans.Next()) ++n;
  EXPECT_EQ(n, 1);
  EXPECT_EQ(reader.stats().skipped_corrupt, 3u);
  ASSERT_FALSE(reader.stats().first_errors.empty());
  EXPECT_NE(reader.stats().first_errors[0].find("far.log:1: FLASER: laser pose is implausibly far"), std::string::npos)
      << reader.stats().first_errors[0];
}

// Exit status of `pslam run <log>` (the real binary), its stderr in 'err'.
int RunCli(const fs::path& log, const fs::path& err) {
  std::string command = PSLAM_CLI_BINARY;
  command += " run --quiet --particles 5 --threads 2 --log " + log.string() + " >/dev/null 2>" + err.string();
  return std::system(command.c_str());
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST_F(CarmenLimitsTest, PslamRunOnTrillionMetrePosesFailsWithAClearError) {
  const fs::path log = Write("far.log", Log(200, 1e12));
  const int status = RunCli(log, dir_ / "err.txt");
  ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal: " << ReadText(dir_ / "err.txt");
  EXPECT_EQ(WEXITSTATUS(status), 1) << ReadText(dir_ / "err.txt");
  EXPECT_NE(ReadText(dir_ / "err.txt").find("implausibly far"), std::string::npos) << ReadText(dir_ / "err.txt");
}

// 20 km steps at each scan (from 400 km) stay under the reader's bound but soon leave the map's 100 km extent.
TEST_F(CarmenLimitsTest, PslamRunStopsWhenTheMapWouldLeaveItsExtent) {
  const fs::path log = Write("jump.log", Log(30, 4e5));
  const int status = RunCli(log, dir_ / "err.txt");
  ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal: " << ReadText(dir_ / "err.txt");
  EXPECT_EQ(WEXITSTATUS(status), 1) << ReadText(dir_ / "err.txt");
  EXPECT_NE(ReadText(dir_ / "err.txt").find("the map would reach beyond its limits"), std::string::npos)
      << ReadText(dir_ / "err.txt");

  PSlamOptions options;
  options.filter.particles = 5;
  EXPECT_THROW(RunLog(log.string(), options), std::runtime_error);
}

}  // namespace
}  // namespace pslam
