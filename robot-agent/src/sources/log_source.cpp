#include "sources/log_source.hpp"

#include <chrono>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "common/clock.hpp"

namespace pslam::agent {

LogSource::LogSource(LogSourceOptions options) : options_(std::move(options)), reader_(options_.path) {
  // The laser geometry goes into `hello` before anything is sent: read ahead to the first scan.
  while (true) {
    auto event = ReadEvent();
    if (!event) throw std::runtime_error("log " + options_.path + " holds no laser scan");
    lookahead_.push_back(*event);
    if (const auto* scan = std::get_if<LaserScan>(&*event)) {
      laser_ = {scan->angle_min, scan->angle_increment, scan->ranges.size(), scan->max_range, scan->min_range,
                scan->sensor_offset};
      break;
    }
  }
}

std::string LogSource::description() const {
  std::ostringstream out;
  out << "log " << options_.path << " at ";
  if (options_.rate > 0) {
    out << options_.rate << "x real time";
  } else {
    out << "maximum rate";
  }
  return out.str();
}

std::optional<SourceEvent> LogSource::ReadEvent() {
  while (true) {
    if (auto scan = interpolator_.NextReady(0.0)) return SourceEvent(std::move(*scan));
    if (reader_done_) {
      // End of log: release scans still waiting for a later ODOM with the last reading held.
      if (auto scan = interpolator_.NextReady(1e18)) return SourceEvent(std::move(*scan));
      return std::nullopt;
    }
    auto record = reader_.Next();
    if (!record) {
      reader_done_ = true;
      continue;
    }
    if (auto* odom = std::get_if<OdometryReading>(&*record)) {
      interpolator_.AddOdometry(*odom);
      return SourceEvent(*odom);
    }
    auto& scan = std::get<LaserScan>(*record);
    if (reader_.last_scan_has_odometry()) return SourceEvent(std::move(scan));
    interpolator_.AddScan(std::move(scan));
  }
}

bool LogSource::FillLookahead() {
  if (!lookahead_.empty()) return true;
  auto event = ReadEvent();
  if (!event) {
    finished_ = true;
    return false;
  }
  lookahead_.push_back(std::move(*event));
  return true;
}

std::optional<SourceEvent> LogSource::Next(double timeout_s) {
  if (finished_ || !FillLookahead()) return std::nullopt;
  SourceEvent& event = lookahead_.front();
  const double t = std::visit([](const auto& e) { return e.timestamp; }, event);
  if (options_.rate > 0) {
    // Pace by log time: event due at wall_start + (t - t0) / rate.
    if (!first_log_time_) {
      first_log_time_ = t;
      wall_start_ = AgentClock::Now();
    }
    const double due = wall_start_ + (t - *first_log_time_) / options_.rate;
    const double wait = due - AgentClock::Now();
    if (wait > timeout_s) {
      std::this_thread::sleep_for(std::chrono::duration<double>(timeout_s));
      return std::nullopt;
    }
    if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
  }
  return Take();
}

std::optional<SourceEvent> LogSource::Take() {
  if (!FillLookahead()) return std::nullopt;
  SourceEvent out = std::move(lookahead_.front());
  lookahead_.pop_front();
  if (std::holds_alternative<LaserScan>(out) && options_.max_scans > 0 && ++scans_ >= options_.max_scans) {
    finished_ = true;  // this scan is the last one delivered
  }
  return out;
}

std::uint64_t LogSource::Skip(std::uint64_t events) {
  std::uint64_t skipped = 0;
  while (skipped < events && !finished_ && Take()) ++skipped;
  return skipped;
}

std::string LogSource::StatsLine() const {
  const auto& s = reader_.stats();
  std::ostringstream out;
  out << "log " << static_cast<int>(reader_.progress() * 100) << "% read, " << s.skipped_corrupt << " corrupt line(s) skipped";
  return out.str();
}

}  // namespace pslam::agent
