#pragma once
// Runs one session's SlamPipeline on a thread of its own, so that neither the network threads nor
// other sessions ever wait for the filter. Inputs arrive through Push() after they are durably
// stored; the engine publishes live frames (right after an input while the live token bucket has a
// token: 1 / live_period per second on average, bursts of live_burst) and storage checkpoints (every
// checkpoint_period) through callbacks called on its thread.
//
// The input queue has no bound of its own: callers bound it by admission (the ingest stops reading
// from an agent whose unprocessed inputs exceed a limit; a replay waits in WaitForRoom).
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "common/clock.hpp"
#include "engine/engine_output.hpp"
#include "engine/slam_pipeline.hpp"
#include "engine/tile_tracker.hpp"
#include "engine/token_bucket.hpp"
#include "model/input.hpp"
#include "model/session_settings.hpp"

namespace pslam::server {

struct EngineTiming {
  double live_period_seconds = 0.1;  // average spacing of live ticks
  double live_burst = 3;             // ticks that may follow each other without that spacing
  double checkpoint_period_seconds = 2.0;
  double stats_period_seconds = 1.0;  // live stats: a plot's rate, not the filter's
};

struct EngineSinks {
  std::function<void(std::shared_ptr<const LiveFrame>)> live;
  std::function<void(Checkpoint)> checkpoint;
  std::function<void(std::int64_t processed_seq)> progress;
  std::function<void(const ExplorationTarget&)> target;
  std::function<void(const TrackingChange&)> tracking;  // not while rebuilding: reported when first seen
  std::function<void(const ExplorationStatus&)> exploration;  // the state changed; not while rebuilding
  std::function<void(const StuckReport&)> stuck;               // a target was given up; not while rebuilding
  // The filter threw (out of memory, the memory limit, ...). The engine has already dropped its
  // pipeline (the memory) and takes no more inputs; nothing of the engine runs after this returns.
  std::function<void(const std::string& error)> failed;
  // A pose set over REST (SetInitialPose) was applied before the input 'seq'.
  std::function<void(std::int64_t seq, const InitialPose&)> pose_applied;
  std::function<void()> rebuilt;   // the stored inputs of a resumed session are all in the filter
  std::function<void()> finished;  // after the final checkpoint of Finish()
};

// Stored inputs with seq > 'after_seq', in order (a chunk; empty when there are no more).
using BacklogReader = std::function<std::vector<InputRecord>(std::int64_t after_seq)>;

// Poses set over REST before a restart, by the seq of the input each was applied before.
using AppliedPoses = std::map<std::int64_t, InitialPose>;

class SessionEngine {
 public:
  // 'site_maps': the site's map, for a session in localize mode (settings.mode), and the site's
  // maps its predictor searches in map mode (SlamPipeline).
  SessionEngine(std::string session_id, SessionSettings settings, LaserGeometry laser, EngineTiming timing,
                EngineSinks sinks, SiteMaps site_maps = {});
  ~SessionEngine();
  SessionEngine(const SessionEngine&) = delete;
  SessionEngine& operator=(const SessionEngine&) = delete;

  // Starts the thread. It first re-runs the stored inputs up to 'backlog_until' through the filter
  // (a resumed session), applying 'applied_poses' before the same inputs as the first time, then
  // takes pushed inputs.
  void Start(BacklogReader backlog, std::int64_t backlog_until, AppliedPoses applied_poses = {});
  // Queues an input; inputs at or below the last processed seq are ignored (exactly once).
  void Push(InputRecord input, SteadyTime received);
  // Blocks until fewer than 'max_queued' inputs wait (replays pace themselves with this).
  void WaitForRoom(std::size_t max_queued);
  // Processes everything queued, writes the final checkpoint (with the best particle's smoothed
  // trajectory), calls sinks.finished and joins. For closing a session.
  void Finish();
  // Stops after the current input, writes a checkpoint and joins. For a server shutdown.
  void Stop();
  // Stops without a checkpoint. For a deleted session.
  void Abort();
  // Skip-predicted exploration: visit the frontiers predictions cover once no other is left (the
  // default), or wait for the operator. Any thread; applies from the next input.
  void SetVerifyPredicted(bool verify) { verify_predicted_ = verify; }
  bool verify_predicted() const { return verify_predicted_.load(); }
  // Localize mode: re-localize from this pose at the next input (any thread).
  void SetInitialPose(const InitialPose& pose);

  const std::string& session_id() const { return session_id_; }
  std::int64_t processed_seq() const { return processed_seq_.load(); }
  std::size_t queued() const;
  bool failed() const { return failed_.load(); }
  // The engine's thread has left its loop (joining it is immediate).
  bool exited() const { return exited_.load(); }
  EngineStats stats() const;
  std::shared_ptr<const LiveFrame> latest_frame() const;

 private:
  enum class StopMode { kNone, kFinish, kStop, kAbort };
  struct Queued {
    InputRecord input;
    SteadyTime received;
  };

  void Loop(BacklogReader backlog, std::int64_t backlog_until);
  void Process(const InputRecord& input, std::optional<SteadyTime> received);
  void ReplaceTrajectory();
  void TakePlan();
  void SendTarget(const ExplorationTarget& target);  // to the viewers and (unless rebuilding) the agent
  void ReportTracking(const InputRecord& input);      // the divergence monitor's state changed at 'input'
  void ReportExploration();                           // after a plan was taken
  void PublishLive(bool final_tick = false);
  bool StatsDue(SteadyTime now) const;
  SteadyTime::duration StatsPeriod() const;
  void WriteCheckpoint(bool final_checkpoint);
  void RecordTiming(double latency_ms, double step_ms);
  EngineStats CurrentStats() const;  // engine thread
  void Join(StopMode mode);

  const std::string session_id_;
  const SessionSettings settings_;
  const LaserGeometry laser_;
  const EngineTiming timing_;
  EngineSinks sinks_;
  SiteMaps site_maps_;  // handed to the pipeline when it is built

  // Engine thread only.
  std::unique_ptr<SlamPipeline> pipeline_;
  TileTracker live_tiles_;
  TileTracker stored_tiles_;
  std::vector<TrajectoryRow> online_;            // per scan: seq, time, online pose estimate
  std::size_t live_trajectory_sent_ = 0;
  std::size_t stored_trajectory_sent_ = 0;
  bool stored_trajectory_replaced_ = false;      // a loop closure rewrote online_ since the last checkpoint
  std::vector<HypothesisRecord> live_hypotheses_, stored_hypotheses_;
  std::vector<std::int64_t> live_removed_;
  std::optional<ExplorationTarget> live_target_;
  std::shared_ptr<const LaserScan> last_scan_;  // for the live laser layer
  bool live_dirty_ = true;
  bool stored_dirty_ = false;
  std::optional<TokenBucket> live_tokens_;
  SteadyTime last_stats_sent_{};
  bool stats_pending_ = false;  // the last tick's stats were not sent to viewers
  SteadyTime last_checkpoint_{};
  std::deque<SteadyTime> recent_scans_;
  std::deque<std::pair<double, double>> recent_timing_;  // (latency ms or -1, step ms)

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable room_;
  std::deque<Queued> queue_;
  StopMode stop_ = StopMode::kNone;
  bool plan_ready_ = false;                              // the planner has a result to take
  std::optional<InitialPose> pending_pose_;              // to apply before the next input
  AppliedPoses replayed_poses_;                          // engine thread only
  EngineStats stats_;                                    // copy for other threads
  std::shared_ptr<const LiveFrame> latest_frame_;
  std::atomic<std::int64_t> processed_seq_{0};
  std::atomic<bool> failed_{false};
  std::atomic<bool> rebuilding_{false};
  std::atomic<bool> exited_{false};
  std::atomic<bool> verify_predicted_{true};
  std::thread thread_;
};

}  // namespace pslam::server
