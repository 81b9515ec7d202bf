// The P2OS client against a simulated Pioneer on a pseudo-terminal.
#include "devices/p2os_client.hpp"

#include <gtest/gtest.h>

#include <mutex>
#include <vector>

#include "fakes/fake_pioneer.hpp"
#include "wait_for.hpp"

namespace pslam::agent {
namespace {

using testing::FakePioneer;
using testing::FakePioneerOptions;
using testing::WaitFor;

struct Collected {
  std::mutex mutex;
  std::vector<OdometryReading> readings;
  void Add(const OdometryReading& r) {
    const std::lock_guard<std::mutex> lock(mutex);
    readings.push_back(r);
  }
  std::size_t size() {
    const std::lock_guard<std::mutex> lock(mutex);
    return readings.size();
  }
  OdometryReading last() {
    const std::lock_guard<std::mutex> lock(mutex);
    return readings.back();
  }
};

P2osClientOptions FastOptions() {
  P2osClientOptions o;
  o.probe_bauds = {9600};
  o.reply_timeout_s = 0.2;
  return o;
}

TEST(P2osClientTest, HandshakeOpenEnableAndStreamOdometry) {
  FakePioneer robot;
  P2osClient client(robot.device(), FastOptions());
  client.Connect();
  EXPECT_EQ(client.identity().subclass, "p3dx-sh");
  Collected odometry;
  client.Start([&](const OdometryReading& r) { odometry.Add(r); });
  ASSERT_TRUE(WaitFor([&] { return odometry.size() >= 5; }, 3.0));
  const auto state = robot.state();
  EXPECT_TRUE(state.open);
  EXPECT_TRUE(state.motors_enabled);
  EXPECT_FALSE(state.sonar_on);
  EXPECT_EQ(state.bad_checksums, 0);
  client.Shutdown();
  EXPECT_TRUE(WaitFor([&] { return !robot.state().open; }, 1.0));  // STOP, ENABLE 0, CLOSE
}

TEST(P2osClientTest, VelocityCommandsMoveTheRobotAndOdometryFollows) {
  FakePioneer robot;
  P2osClient client(robot.device(), FastOptions());
  client.Connect();
  Collected odometry;
  client.Start([&](const OdometryReading& r) { odometry.Add(r); });
  client.SetVelocity(0.5, 0.0);
  ASSERT_TRUE(WaitFor([&] { return robot.state().vel_mm_s == 500; }, 1.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  client.SetVelocity(0.0, 0.5);  // rad/s -> RVEL in deg/s
  ASSERT_TRUE(WaitFor([&] { return robot.state().rvel_deg_s == 29 && robot.state().vel_mm_s == 0; }, 1.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto state = robot.state();
  const auto last = odometry.last();
  EXPECT_NEAR(last.pose.x, state.x_mm / 1000.0, 0.06);  // within one SIP of motion
  EXPECT_GT(last.pose.x, 0.3);
  EXPECT_GT(state.vel_commands, 0);
  EXPECT_GT(state.rvel_commands, 0);
  client.Shutdown();
}

TEST(P2osClientTest, WrapAroundDoesNotJump) {
  FakePioneerOptions options;
  options.start_x = 0x7F80;  // 128 mm before the 15-bit wrap
  options.sip_period_s = 0.05;
  FakePioneer robot(options);
  P2osClient client(robot.device(), FastOptions());
  client.Connect();
  Collected odometry;
  client.Start([&](const OdometryReading& r) { odometry.Add(r); });
  client.SetVelocity(0.8, 0.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  client.Shutdown();
  const std::lock_guard<std::mutex> lock(odometry.mutex);
  ASSERT_GT(odometry.readings.size(), 10u);
  // A wrong wrap jumps by 32.768 m or more. The fake moves by the wall-clock time since its last
  // SIP, at most 0.5 s of it, so a loaded machine may see steps of up to 0.8 m/s * 0.5 s.
  const double largest_step = 0.8 * 0.5 + 0.01;
  for (std::size_t i = 1; i < odometry.readings.size(); ++i) {
    EXPECT_GE(odometry.readings[i].pose.x - odometry.readings[i - 1].pose.x, -1e-9);
    EXPECT_LT(odometry.readings[i].pose.x - odometry.readings[i - 1].pose.x, largest_step);
  }
  EXPECT_GT(odometry.readings.back().pose.x - odometry.readings.front().pose.x, 0.5);
}

TEST(P2osClientTest, KeepAlivePulsesHoldOffTheWatchdog) {
  FakePioneerOptions options;
  options.watchdog_s = 0.8;
  FakePioneer robot(options);
  P2osClient client(robot.device(), FastOptions());
  client.Connect();
  client.Start([](const OdometryReading&) {});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_GE(robot.state().pulses, 2);  // no velocity ever commanded: PULSE only
  client.SetVelocity(0.2, 0.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_EQ(robot.state().watchdog_trips, 0);
  EXPECT_EQ(robot.state().vel_mm_s, 200);
  client.Shutdown();
}

TEST(P2osClientTest, CorruptSplitAndNoisyFramesAreCountedAndSkipped) {
  FakePioneerOptions options;
  options.corrupt_every_nth_sip = 3;
  options.split_sips = true;
  options.sip_period_s = 0.05;
  FakePioneer robot(options);
  P2osClient client(robot.device(), FastOptions());
  client.Connect();
  Collected odometry;
  client.Start([&](const OdometryReading& r) { odometry.Add(r); });
  ASSERT_TRUE(WaitFor([&] { return odometry.size() >= 12; }, 5.0));
  const auto stats = client.stats();
  EXPECT_GE(stats.parser.bad_checksum, 4u);
  EXPECT_GE(stats.sips, 12u);
  EXPECT_FALSE(stats.fault);
  client.Shutdown();
}

TEST(P2osClientTest, NoiseBetweenPacketsIsSkipped) {
  FakePioneerOptions options;
  options.noise_between_packets = true;
  options.sip_period_s = 0.05;
  FakePioneer robot(options);
  P2osClient client(robot.device(), FastOptions());
  client.Connect();
  Collected odometry;
  client.Start([&](const OdometryReading& r) { odometry.Add(r); });
  ASSERT_TRUE(WaitFor([&] { return odometry.size() >= 5; }, 3.0));
  EXPECT_GT(client.stats().parser.skipped_bytes, 0u);
  client.Shutdown();
}

TEST(P2osClientTest, RobotLeftOpenByAPreviousClientIsClosedAndResynced) {
  FakePioneerOptions options;
  options.open_at_start = true;
  FakePioneer robot(options);
  P2osClient client(robot.device(), FastOptions());
  client.Connect();
  EXPECT_GE(robot.state().closes, 1);
  EXPECT_TRUE(robot.state().open);
  client.Shutdown();
}

TEST(P2osClientTest, SilentPortGivesAClearError) {
  testing::PtyPair nobody;
  P2osClientOptions o = FastOptions();
  o.reply_timeout_s = 0.05;
  o.sync_attempts_per_baud = 2;
  P2osClient client(nobody.slave_path(), o);
  try {
    client.Connect();
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no Pioneer answered"), std::string::npos) << e.what();
  }
}

TEST(P2osClientTest, LostSipsAreAFaultAndTheHandshakeIsRedone) {
  FakePioneer robot;
  P2osClientOptions o = FastOptions();
  o.sip_timeout_s = 0.3;
  o.reconnect_after_s = 0.6;
  P2osClient client(robot.device(), o);
  client.Connect();
  client.Start([](const OdometryReading&) {});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  robot.set_sips_enabled(false);
  ASSERT_TRUE(WaitFor([&] { return client.stats().fault; }, 2.0));
  robot.set_sips_enabled(true);
  ASSERT_TRUE(WaitFor([&] { return !client.stats().fault; }, 3.0));
  client.Shutdown();
}

}  // namespace
}  // namespace pslam::agent
