#pragma once
// The seam between the server and the SLAM core: one session's mapping pipeline, synchronous and
// single-threaded (SessionEngine runs it on the session's thread). Today it is the particle filter
// (pslam::Rbpf); the P-SLAM structure predictor plugs in here, behind the same outputs: the
// hypotheses it adds or updates, frontiers and the next exploration target. Nothing in the network
// or storage code changes when it does.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "model/hypothesis.hpp"
#include "model/input.hpp"
#include "model/session_settings.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/sensor/laser_scan.hpp"

namespace pslam::server {

// What one input changed.
struct PipelineStep {
  bool scan = false;                              // the input was a scan (odometry only updates state)
  RbpfStep filter;                                // for scans
  std::vector<HypothesisRecord> hypotheses_changed;  // added or updated by this input
  std::vector<std::int64_t> hypotheses_removed;
  std::optional<ExplorationTarget> target;        // a newly planned target, if any
};

// The LaserScan for a stored scan input of a session with laser 'laser'. Ranges that are not
// finite (NaN: no return) stay so; the filter treats them as beams without a return.
LaserScan ToLaserScan(const InputRecord& input, const LaserGeometry& laser);

RbpfOptions ToRbpfOptions(const SessionSettings& settings);

class SlamPipeline {
 public:
  SlamPipeline(const SessionSettings& settings, const LaserGeometry& laser);
  SlamPipeline(const SlamPipeline&) = delete;
  SlamPipeline& operator=(const SlamPipeline&) = delete;

  PipelineStep Add(const InputRecord& input);

  const OccupancyGrid& map() const { return filter_.best().map; }
  bool started() const { return !filter_.particles().empty(); }
  const RbpfStats& filter_stats() const { return filter_.stats(); }
  int particle_count() const { return static_cast<int>(filter_.particles().size()); }
  std::vector<Pose2D> ParticlePoses() const;
  std::vector<double> Weights() const { return filter_.Weights(); }
  // The best particle's pose at every scan so far (smoothed: see Rbpf::Trajectory).
  std::vector<Pose2D> Trajectory() const { return filter_.Trajectory(); }

  // P-SLAM outputs. The predictor is not in the core yet, so these stay empty.
  // TODO(lead): run the structure predictor in Add() when settings.predict is set, and fill these.
  const std::vector<HypothesisRecord>& hypotheses() const { return hypotheses_; }
  const std::vector<std::array<double, 2>>& frontiers() const { return frontiers_; }
  const std::optional<ExplorationTarget>& target() const { return target_; }

 private:
  SessionSettings settings_;
  LaserGeometry laser_;
  Rbpf filter_;
  std::vector<HypothesisRecord> hypotheses_;
  std::vector<std::array<double, 2>> frontiers_;
  std::optional<ExplorationTarget> target_;
};

}  // namespace pslam::server
