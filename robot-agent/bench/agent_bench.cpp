// pslam-agent-bench: the performance targets, measured on the real agent pipeline.
//
//   * live: the Pioneer source reading a simulated P3-DX (10 Hz SIPs) and LMS-200 (75 scans/s,
//     181 beams) over pseudo-terminals, the spool on disk, the link to an ingest server on
//     loopback. Target: <= 5 % of one core and <= 50 MB resident.
//   * link drop: the server is killed for a while (the agent keeps spooling), then restarted.
//     Target: the backlog drains at >= 10x the live message rate.
//
// The device simulators and the server run in separate processes (this binary re-executed with
// --serve-devices / --serve-ingest), so getrusage(RUSAGE_SELF) counts only the agent.
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "agent.hpp"
#include "common/clock.hpp"
#include "common/log.hpp"
#include "fakes/fake_ingest_server.hpp"
#include "fakes/fake_pioneer.hpp"
#include "fakes/fake_sick.hpp"
#include "sources/pioneer_source.hpp"

extern char** environ;

namespace pslam::agent {
namespace {

void SleepS(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

struct Child {
  pid_t pid = -1;
  FILE* out = nullptr;  // the child's stdout
};

Child Spawn(const std::vector<std::string>& args) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  Child c;
  if (posix_spawn(&c.pid, "/proc/self/exe", &actions, nullptr, argv.data(), environ) != 0) throw std::runtime_error("spawn");
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  c.out = ::fdopen(fds[0], "r");
  return c;
}

std::string ReadLine(FILE* f) {
  char buf[512];
  if (!std::fgets(buf, sizeof buf, f)) throw std::runtime_error("child exited early");
  std::string s(buf);
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

void Kill(Child& c) {
  if (c.pid <= 0) return;
  ::kill(c.pid, SIGKILL);
  ::waitpid(c.pid, nullptr, 0);
  std::fclose(c.out);
  c.pid = -1;
}

int ServeIngest(unsigned short port) {
  testing::FakeIngestServer server;
  std::printf("%u\n", server.Start(port));
  std::fflush(stdout);
  while (true) SleepS(1.0);
}

int ServeDevices() {
  testing::FakePioneer robot;
  testing::FakeSick laser;  // 75 scans/s
  std::printf("%s\n%s\n", robot.device().c_str(), laser.device().c_str());
  std::fflush(stdout);
  while (true) SleepS(1.0);
}

double CpuSeconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_utime.tv_usec * 1e-6 + u.ru_stime.tv_sec + u.ru_stime.tv_usec * 1e-6;
}

double PeakRssMb() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

double CurrentRssMb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0;
}

int Bench(double live_s, double drop_s) {
  SetLogLevel(LogLevel::kWarning);
  Child devices = Spawn({"pslam-agent-bench", "--serve-devices"});
  const std::string robot_device = ReadLine(devices.out);
  const std::string laser_device = ReadLine(devices.out);
  Child server = Spawn({"pslam-agent-bench", "--serve-ingest", "0"});
  const unsigned short port = static_cast<unsigned short>(std::stoi(ReadLine(server.out)));

  const auto spool_dir = std::filesystem::temp_directory_path() / ("pslam-agent-bench-" + std::to_string(::getpid()));
  std::filesystem::remove_all(spool_dir);
  AgentOptions o;
  o.server_host = "127.0.0.1";
  o.server_port = std::to_string(port);
  o.token = "secret";
  o.spool_dir = spool_dir.string();
  o.drive = false;
  o.status_period_s = 1e9;
  PioneerSourceOptions p;
  p.robot_device = robot_device;
  p.laser_device = laser_device;
  p.robot.probe_bauds = {9600};
  p.robot.enable_motors = false;
  p.laser.probe_timeout_s = 0.3;

  Agent agent(o, std::make_unique<PioneerSource>(p));
  std::atomic<bool> stop{false};
  std::thread runner([&] { agent.Run(stop); });
  SleepS(3.0);  // connect, settle

  // Live phase.
  const double cpu0 = CpuSeconds(), wall0 = AgentClock::Now();
  const auto spool0 = agent.spool_stats();
  double rss_max = 0;
  while (AgentClock::Now() - wall0 < live_s) {
    SleepS(0.5);
    rss_max = std::max(rss_max, CurrentRssMb());
  }
  const double cpu1 = CpuSeconds(), wall1 = AgentClock::Now();
  const auto spool1 = agent.spool_stats();
  const double live_rate = (spool1.next_seq - spool0.next_seq) / (wall1 - wall0);
  const double cpu_percent = 100.0 * (cpu1 - cpu0) / (wall1 - wall0);
  std::printf("live: %.1f s, %.1f messages/s (scans + odometry), agent CPU %.2f %% of one core, RSS %.1f MB "
              "(max sampled), unacked at end %llu\n",
              wall1 - wall0, live_rate, cpu_percent, std::max(rss_max, PeakRssMb()),
              static_cast<unsigned long long>(spool1.unacked_records));

  // Link drop.
  Kill(server);
  SleepS(drop_s);
  const auto before = agent.spool_stats();
  const double cpu2 = CpuSeconds();
  server = Spawn({"pslam-agent-bench", "--serve-ingest", std::to_string(port)});
  ReadLine(server.out);
  const double restart = AgentClock::Now();
  const auto backlog = before.unacked_records;
  const std::size_t connections = agent.link_status().connections;
  double reconnected = 0;
  // Drained: back to the live steady state (a few in flight).
  while (agent.spool_stats().unacked_records > 50 && AgentClock::Now() - restart < 120) {
    if (reconnected == 0 && agent.link_status().connections > connections) reconnected = AgentClock::Now();
    SleepS(0.002);
  }
  const double drained = AgentClock::Now();
  const auto after = agent.spool_stats();
  const double sent = static_cast<double>(backlog) + (after.next_seq - before.next_seq) -
                      static_cast<double>(after.unacked_records);
  const double drain_rate = sent / (drained - restart);
  if (reconnected == 0) reconnected = drained;
  std::printf("link drop: %.1f s down, backlog %llu messages (%.1f MB spooled), drained %.2f s after the server came "
              "back (of which %.2f s reconnect back-off): %.0f messages/s = %.1fx the live rate (transfer alone: "
              "%.0f messages/s); agent CPU during drain %.0f %%\n",
              drop_s, static_cast<unsigned long long>(backlog), before.bytes / 1048576.0, drained - restart,
              reconnected - restart, drain_rate, drain_rate / live_rate, sent / std::max(drained - reconnected, 1e-3),
              100.0 * (CpuSeconds() - cpu2) / (drained - restart));
  const double peak_rss = std::max(PeakRssMb(), CurrentRssMb());
  std::printf("peak RSS over the whole run: %.1f MB\n", peak_rss);
  // The drain target is judged on the whole time from the server's return, back-off included.
  const bool ok = cpu_percent <= 5.0 && peak_rss <= 50.0 && drain_rate >= 10 * live_rate;
  std::printf("targets (<= 5 %% CPU: %.2f %%, <= 50 MB: %.1f MB, drain >= 10x live: %.1fx): %s\n", cpu_percent, peak_rss,
              drain_rate / live_rate, ok ? "MET" : "NOT MET");

  stop = true;
  runner.join();
  Kill(server);
  Kill(devices);
  std::filesystem::remove_all(spool_dir);
  return ok ? 0 : 1;
}

}  // namespace
}  // namespace pslam::agent

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.size() == 2 && args[0] == "--serve-ingest") return pslam::agent::ServeIngest(static_cast<unsigned short>(std::stoi(args[1])));
    if (args.size() == 1 && args[0] == "--serve-devices") return pslam::agent::ServeDevices();
    double live = 30, drop = 20;
    for (std::size_t i = 0; i + 1 < args.size(); i += 2) {
      if (args[i] == "--live-seconds") live = std::stod(args[i + 1]);
      else if (args[i] == "--drop-seconds") drop = std::stod(args[i + 1]);
      else throw std::runtime_error("usage: pslam-agent-bench [--live-seconds S] [--drop-seconds S]");
    }
    return pslam::agent::Bench(live, drop);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pslam-agent-bench: %s\n", e.what());
    return 2;
  }
}
