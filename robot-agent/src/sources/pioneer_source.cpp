#include "sources/pioneer_source.hpp"

#include <chrono>
#include <sstream>

#include "common/clock.hpp"
#include "common/log.hpp"

namespace pslam::agent {

PioneerSource::PioneerSource(PioneerSourceOptions options) : options_(std::move(options)) {
  robot_ = std::make_unique<P2osClient>(options_.robot_device, options_.robot);
  laser_ = std::make_unique<SickClient>(options_.laser_device, options_.laser);
  robot_->Connect();
  laser_->Connect();
  robot_->Start([this](const OdometryReading& odom) { Push(odom); });
  const LaserDescription geometry = laser();
  laser_->Start([this, geometry](const SickScan& s) {
    LaserScan scan;
    scan.timestamp = s.time;
    scan.ranges = s.ranges_m;
    scan.angle_min = geometry.angle_min;
    scan.angle_increment = geometry.angle_increment;
    scan.max_range = geometry.max_range;
    scan.min_range = geometry.min_range;
    scan.sensor_offset = geometry.offset;
    Push(std::move(scan));
  });
}

PioneerSource::~PioneerSource() { Shutdown(); }

void PioneerSource::Shutdown() {
  if (laser_) laser_->Shutdown();
  if (robot_) robot_->Shutdown();
}

std::string PioneerSource::description() const {
  return "pioneer " + robot_->identity().name + " (" + robot_->identity().subclass + ") on " + options_.robot_device +
         ", LMS-200 on " + options_.laser_device;
}

LaserDescription PioneerSource::laser() const {
  return {laser_->angle_min_rad(), laser_->angle_increment_rad(), laser_->beams(), laser_->max_range_m(), 0.0,
          options_.laser_offset};
}

void PioneerSource::Push(SourceEvent event) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.size() >= options_.max_queued_events) {
      queue_.pop_front();  // the device threads never block on a stalled agent
      ++dropped_;
    }
    queue_.push_back(std::move(event));
  }
  ready_.notify_one();
}

std::optional<SourceEvent> PioneerSource::Next(double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(timeout_s));
  while (true) {
    if (auto scan = interpolator_.NextReady(AgentClock::Now())) out_.push_back(std::move(*scan));
    if (!out_.empty()) {
      SourceEvent e = std::move(out_.front());
      out_.pop_front();
      return e;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    // Wake at least every 50 ms so a scan whose odometry never comes is released after max wait.
    const auto wake = std::min(deadline, std::chrono::steady_clock::now() + std::chrono::milliseconds(50));
    if (!ready_.wait_until(lock, wake, [this] { return !queue_.empty(); })) {
      if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
      continue;
    }
    SourceEvent e = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    if (auto* odom = std::get_if<OdometryReading>(&e)) {
      interpolator_.AddOdometry(*odom);
      out_.push_back(std::move(e));
    } else {
      interpolator_.AddScan(std::move(std::get<LaserScan>(e)));
    }
  }
}

std::string PioneerSource::StatsLine() const {
  const P2osClientStats r = robot_->stats();
  const SickClientStats l = laser_->stats();
  std::size_t dropped = 0;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    dropped = dropped_;
  }
  std::ostringstream out;
  out << "robot: " << r.sips << " SIPs, " << r.parser.bad_checksum << " bad checksum, " << r.parser.bad_length
      << " bad length, " << r.parser.skipped_bytes << " noise bytes" << (r.fault ? ", NO SIPS" : "")
      << "; laser: " << l.scans << " scans, " << l.parser.bad_crc << " bad CRC, " << l.bad_scans << " bad scans, "
      << l.parser.skipped_bytes << " noise bytes; " << interpolator_.held_scans() << " scans without later odometry, "
      << dropped << " events dropped";
  return out.str();
}

}  // namespace pslam::agent
