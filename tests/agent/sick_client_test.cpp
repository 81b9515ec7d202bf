// The LMS-200 client against a simulated scanner on a pseudo-terminal.
#include "devices/sick_client.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <mutex>
#include <vector>

#include "fakes/fake_sick.hpp"
#include "wait_for.hpp"

namespace pslam::agent {
namespace {

using testing::FakeSick;
using testing::FakeSickOptions;
using testing::WaitFor;

struct Scans {
  std::mutex mutex;
  std::vector<SickScan> scans;
  void Add(const SickScan& s) {
    const std::lock_guard<std::mutex> lock(mutex);
    scans.push_back(s);
  }
  std::size_t size() {
    const std::lock_guard<std::mutex> lock(mutex);
    return scans.size();
  }
};

SickClientOptions FastOptions() {
  SickClientOptions o;
  o.probe_timeout_s = 0.3;
  o.reply_timeout_s = 1.0;
  return o;
}

TEST(SickClientTest, SwitchesTo500kStreamsAndDecodes) {
  FakeSick laser;
  SickClient client(laser.device(), FastOptions());
  client.Connect();
  EXPECT_EQ(laser.state().baud, 500000);
  EXPECT_TRUE(laser.state().streaming);
  EXPECT_EQ(client.beams(), 181u);
  EXPECT_NEAR(client.angle_min_rad(), -M_PI / 2, 1e-12);
  EXPECT_NEAR(client.max_range_m(), 8.191, 1e-9);
  Scans scans;
  client.Start([&](const SickScan& s) { scans.Add(s); });
  ASSERT_TRUE(WaitFor([&] { return scans.size() >= 75; }, 3.0));
  {
    const std::lock_guard<std::mutex> lock(scans.mutex);
    const SickScan& s = scans.scans.back();
    ASSERT_EQ(s.ranges_m.size(), 181u);
    EXPECT_FLOAT_EQ(s.ranges_m[0], 2.0f);
    EXPECT_TRUE(std::isnan(s.ranges_m[45]));  // 8191: no echo
    // About 75 per second, stamped in increasing order.
    const double span = scans.scans.back().time - scans.scans.front().time;
    EXPECT_NEAR((scans.scans.size() - 1) / span, 75.0, 10.0);
    for (std::size_t i = 1; i < scans.scans.size(); ++i) EXPECT_GT(scans.scans[i].time, scans.scans[i - 1].time);
  }
  client.Shutdown();
  EXPECT_TRUE(WaitFor([&] { return !laser.state().streaming; }, 1.0));  // back to polled mode
}

TEST(SickClientTest, ScannerAlreadyAtTargetRateNeedsNoSwitch) {
  FakeSickOptions o;
  o.power_on_baud = 38400;
  FakeSick laser(o);
  SickClientOptions c = FastOptions();
  c.baud = 38400;
  SickClient client(laser.device(), c);
  client.Connect();
  EXPECT_EQ(laser.state().baud, 38400);
  client.Shutdown();
}

TEST(SickClientTest, CorruptSplitAndNoisyTelegramsAreCountedAndSkipped) {
  FakeSickOptions o;
  o.corrupt_every_nth_scan = 4;
  o.split_scans = true;
  o.noise_between_telegrams = true;
  FakeSick laser(o);
  SickClient client(laser.device(), FastOptions());
  client.Connect();
  Scans scans;
  client.Start([&](const SickScan& s) { scans.Add(s); });
  ASSERT_TRUE(WaitFor([&] { return scans.size() >= 60; }, 4.0));
  client.Shutdown();
  const auto stats = client.stats();
  EXPECT_GE(stats.parser.bad_crc, 15u);
  EXPECT_GT(stats.parser.skipped_bytes, 0u);
  // Every delivered scan is a good one.
  const std::lock_guard<std::mutex> lock(scans.mutex);
  for (const auto& s : scans.scans) {
    ASSERT_EQ(s.ranges_m.size(), 181u);
    EXPECT_FLOAT_EQ(s.ranges_m[100], 2.0f);
  }
  // One in four was corrupted: about three quarters get through.
  const double delivered = static_cast<double>(stats.scans) / laser.state().scans_sent;
  EXPECT_NEAR(delivered, 0.75, 0.1);
}

TEST(SickClientTest, MeasuringModeFromConfigurationSelectsDistanceBits) {
  FakeSickOptions o;
  o.measuring_mode = 0x05;  // 15-bit distances, 32 m
  o.range_mm = [](int beam, int) { return static_cast<std::uint16_t>(beam == 0 ? 20000 : 1000); };
  FakeSick laser(o);
  SickClient client(laser.device(), FastOptions());
  client.Connect();
  EXPECT_NEAR(client.max_range_m(), 32.767, 1e-9);
  Scans scans;
  client.Start([&](const SickScan& s) { scans.Add(s); });
  ASSERT_TRUE(WaitFor([&] { return scans.size() >= 1; }, 2.0));
  client.Shutdown();
  const std::lock_guard<std::mutex> lock(scans.mutex);
  EXPECT_FLOAT_EQ(scans.scans.front().ranges_m[0], 20.0f);
}

TEST(SickClientTest, HalfDegreeVariant) {
  FakeSick laser;
  SickClientOptions c = FastOptions();
  c.resolution_centideg = 50;
  SickClient client(laser.device(), c);
  client.Connect();
  EXPECT_EQ(client.beams(), 361u);
  EXPECT_EQ(laser.state().resolution_cdeg, 50);
  Scans scans;
  client.Start([&](const SickScan& s) { scans.Add(s); });
  ASSERT_TRUE(WaitFor([&] { return scans.size() >= 2; }, 2.0));
  client.Shutdown();
}

TEST(SickClientTest, SilentPortGivesAClearError) {
  testing::PtyPair nobody;
  SickClientOptions c = FastOptions();
  c.probe_timeout_s = 0.05;
  SickClient client(nobody.slave_path(), c);
  try {
    client.Connect();
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no SICK LMS-200 answered"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pslam::agent
