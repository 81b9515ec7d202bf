#include "engine/slam_pipeline.hpp"

namespace pslam::server {

LaserScan ToLaserScan(const InputRecord& input, const LaserGeometry& laser) {
  LaserScan scan;
  scan.timestamp = input.t;
  scan.timestamp_text = input.stamp;
  scan.ranges = input.ranges;
  scan.angle_min = laser.angle_min;
  scan.angle_increment = laser.angle_increment;
  scan.max_range = laser.max_range;
  scan.min_range = laser.min_range;
  scan.sensor_offset = Pose2D(laser.offset_x, laser.offset_y, laser.offset_theta);
  scan.odometry = Pose2D(input.x, input.y, input.theta);
  return scan;
}

RbpfOptions ToRbpfOptions(const SessionSettings& settings) {
  RbpfOptions options;
  options.particles = settings.particles;
  options.seed = settings.seed;
  options.threads = settings.threads;
  options.resolution = settings.resolution;
  options.linear_update = settings.linear_update;
  options.angular_update = settings.angular_update;
  options.resample_threshold = settings.resample_threshold;
  return options;
}

SlamPipeline::SlamPipeline(const SessionSettings& settings, const LaserGeometry& laser)
    : settings_(settings), laser_(laser), filter_(ToRbpfOptions(settings)) {}

PipelineStep SlamPipeline::Add(const InputRecord& input) {
  PipelineStep step;
  // Odometry messages are stored for replay and for the predictor's motion cues; the filter takes
  // the odometry that each scan carries (interpolated by the agent to the scan time).
  if (input.kind != InputKind::kScan) return step;
  step.scan = true;
  step.filter = filter_.AddScan(ToLaserScan(input, laser_));
  return step;
}

std::vector<Pose2D> SlamPipeline::ParticlePoses() const {
  std::vector<Pose2D> poses;
  poses.reserve(filter_.particles().size());
  for (const Particle& p : filter_.particles()) poses.push_back(p.pose);
  return poses;
}

}  // namespace pslam::server
