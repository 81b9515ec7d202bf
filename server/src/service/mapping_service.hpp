#pragma once
// Owns the running sessions: creates them, admits their inputs exactly once, stores them before
// acknowledging, feeds them to each session's engine, and closes, deletes or resumes them. Thread
// safe; nothing here runs on a network thread for long (durable writes go to the StorageWriter,
// filtering to the engines). Methods that wait for storage (CreateSession, CloseSession, ...) are
// for the REST worker threads only.
#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "common/recent_failure.hpp"
#include "engine/engine_output.hpp"
#include "engine/session_engine.hpp"
#include "service/agent_link.hpp"
#include "service/ingest_codec.hpp"
#include "service/live_codec.hpp"
#include "service/session_runtime.hpp"
#include "service/settings_codec.hpp"
#include "storage/read_pool.hpp"
#include "storage/storage_writer.hpp"

namespace pslam::server {

class ClusterCoordinator;

inline constexpr int kMaxRebuilds = 3;

struct ServiceOptions {
  SessionSettings defaults;
  SettingsLimits limits;
  EngineTiming timing;
  std::int64_t max_inflight = 256;   // per session: inputs admitted but not yet in the filter
  std::size_t max_running_sessions = 16;
  bool resume_on_restart = true;     // false: sessions left active are rebuilt and closed
};

// The current map of a session: live from the engine, or rebuilt from the stored tiles.
struct MapView {
  std::shared_ptr<const OccupancyGrid> grid;  // null: nothing mapped yet
  double resolution = 0.05;
  bool live = false;
};

class MappingService {
 public:
  using LiveSink = std::function<void(const std::string& session_id, std::shared_ptr<const LiveFrame> frame)>;
  using EndSink = std::function<void(const std::string& session_id, const std::string& status)>;

  MappingService(ServiceOptions options, StorageWriter& writer, ReadPool& reads);
  ~MappingService();
  MappingService(const MappingService&) = delete;
  MappingService& operator=(const MappingService&) = delete;

  // Where engines send live frames, and who hears that a session stopped running. Set before Recover.
  void SetLiveSinks(LiveSink live, EndSink ended);
  // Makes this server a node of a fleet (docs/fleet.md): a session runs here only while the node
  // holds its lease, and sessions left active are taken over by the coordinator, not by Recover.
  // Set before Recover; 'cluster' must outlive the service's sessions.
  void SetCluster(ClusterCoordinator* cluster) { cluster_ = cluster; }
  // The coordinator's hooks (its thread): this node won the lease of a session nobody ran, or
  // lost the lease of one it runs (the new owner rebuilds it; nothing is written here any more).
  void Adopt(const std::string& id, std::int64_t lease_epoch);
  void Abandon(const std::string& id);
  // Rebalancing: stops the session here with a checkpoint, waits until everything it wrote is
  // committed, and tells its agent to reconnect. False if it does not run here.
  bool HandOver(const std::string& id);
  // At start-up: every session left active is rebuilt from its stored inputs and resumed (or,
  // with resume_on_restart off, closed once rebuilt). A session whose rebuild of the same stored
  // inputs began at kMaxRebuilds start-ups in a row without completing (it took the server down)
  // is quarantined: marked failed instead.
  void Recover();
  // Stops every engine after its current input with a checkpoint. The writer is stopped by its owner.
  void Shutdown();

  // ---- Agent protocol (called on network threads; non-blocking) ----
  struct AgentOpen {
    std::shared_ptr<SessionRuntime> runtime;
    std::int64_t last_acked_seq = 0;
    std::optional<IngestError> error;
    std::string redirect;  // HOST:PORT of the node that runs (or is to run) the session

    static AgentOpen Opened(std::shared_ptr<SessionRuntime> runtime, std::int64_t last_acked_seq) {
      AgentOpen o;
      o.runtime = std::move(runtime);
      o.last_acked_seq = last_acked_seq;
      return o;
    }
    static AgentOpen Failed(IngestError error) {
      AgentOpen o;
      o.error = std::move(error);
      return o;
    }
    static AgentOpen Redirect(std::string address) {
      AgentOpen o;
      o.redirect = std::move(address);
      return o;
    }
  };
  // Creates or resumes the session named by 'hello' for 'link'. 'done' runs once the session is
  // durably created (on the storage thread) or at once for a resume or an error.
  void OpenForAgent(const HelloMessage& hello, const std::shared_ptr<AgentLink>& link,
                    std::function<void(AgentOpen)> done);

  // kImplausible: the input's odometry jumped too far from the last one's (problem says how).
  enum class Admission { kAccepted, kDuplicate, kOutOfOrder, kClosed, kNotOwner, kImplausible };
  struct AdmitResult {
    Admission admission = Admission::kAccepted;
    std::string problem;
    std::int64_t expected_seq = 0;   // the next seq the session takes
    std::int64_t committed_seq = 0;  // everything up to here is acknowledged
  };
  // Admits one input from 'link' (null: a replay feeder). Accepted inputs are stored, then
  // acknowledged to the session's agent and queued for the engine, in seq order.
  AdmitResult Admit(const std::shared_ptr<SessionRuntime>& runtime, const AgentLink* link, InputRecord input);
  // True if the session has more work in flight than allowed; then the agent link is resumed
  // (AgentLink::Resume) once it has fallen to half.
  bool PauseIfOverloaded(const std::shared_ptr<SessionRuntime>& runtime);
  // Blocks until the session has room for another input (replay feeders).
  void WaitForRoom(const std::shared_ptr<SessionRuntime>& runtime);
  void Detach(const std::shared_ptr<SessionRuntime>& runtime, const AgentLink* link);

  // ---- Sessions (REST worker threads; may block on storage) ----
  SessionRow CreateSession(const nlohmann::json& body);
  // Starts a session of 'source' with the given settings and no inputs yet (replays).
  std::shared_ptr<SessionRuntime> StartSession(SessionRow row, const SessionSettings& settings,
                                               const LaserGeometry& laser);
  SessionRow GetSession(const std::string& id);  // throws ApiError 404
  SessionPage ListSessions(const SessionFilter& filter);
  // Drains the engine, writes the final map and trajectory, marks the session closed.
  SessionRow CloseSession(const std::string& id, const std::string& status = "closed");
  void DeleteSession(const std::string& id);
  nlohmann::json Statistics(const std::string& id);
  // Skip-predicted exploration of a running agent session: whether the robot goes on to verify the
  // frontiers that predictions cover (SessionEngine::SetVerifyPredicted). Throws ApiError 404, or
  // 409 for a session that is not running or has no robot.
  bool SetVerifyPredicted(const std::string& id, bool verify);
  // Localize mode: re-localize a running session from the pose in 'body' ({"x", "y", "theta",
  // "std_xy", "std_theta"}) at its next input. Throws ApiError 404, 400, or 409 for a session that
  // is not running or does not localize.
  InitialPose SetInitialPose(const std::string& id, const nlohmann::json& body);
  MapView CurrentMap(const std::string& id);
  std::vector<LiveMessage> StoredLiveSnapshot(const std::string& id);
  // The poses set over REST that a resumed session applied before a restart.
  AppliedPoses LoadAppliedPoses(const std::string& id);
  void LogEvent(const std::optional<std::string>& session_id, const std::string& kind, nlohmann::json detail);

  std::shared_ptr<SessionRuntime> Running(const std::string& id) const;
  std::size_t running_sessions() const;
  std::vector<std::string> running_session_ids() const;
  const ServiceOptions& options() const { return options_; }
  StorageWriter& writer() { return writer_; }
  ReadPool& reads() { return reads_; }
  const RecentFailure& engine_failures() const { return engine_failures_; }

 private:
  std::string NewSessionId();
  void CreateForAgent(const HelloMessage& hello, const std::shared_ptr<AgentLink>& link,
                      std::function<void(AgentOpen)> done);
  // A fleet node: the session of the hello is not running here; on the coordinator's thread.
  void ClaimForAgent(const HelloMessage& hello, const std::shared_ptr<AgentLink>& link,
                     std::function<void(AgentOpen)> done);
  void AttachAgent(const std::shared_ptr<SessionRuntime>& rt, const HelloMessage& hello,
                   const std::shared_ptr<AgentLink>& link, const std::function<void(AgentOpen)>& done);
  IngestError UnknownSession(const std::string& id);
  // Rebuilds a session left active (a restart, or a node that died) from its stored inputs and
  // resumes it; null if it was quarantined or cannot be resumed (it is then marked failed).
  std::shared_ptr<SessionRuntime> ResumeStored(const SessionRow& row, std::int64_t lease_epoch);
  // A fleet node: throws ApiError 307 if another live node runs the session.
  void ThrowIfElsewhere(const std::string& id);
  void ReleaseLease(const std::string& id);
  // A session taken out of running_ stops at once: its agent is told why ('code') and let go,
  // its engine stops without a checkpoint (deleted, or another node runs it now).
  void StopWithoutCheckpoint(SessionRuntime& rt, const std::string& code, const std::string& why);
  // Checks the site a session names and, in localize mode, loads the site's map (its latest version
  // unless the settings name one; the settings then name the version loaded and take its
  // resolution); in map mode, the site's latest kSiteLibraryVersions maps for the predictor.
  // Throws ApiError 400 for a missing site or map.
  SiteMaps PrepareSite(SessionSettings& settings);
  std::shared_ptr<SessionRuntime> Launch(const SessionRow& row, const SessionSettings& settings,
                                         const LaserGeometry& laser, std::int64_t stored_seq, SiteMaps site_maps,
                                         std::int64_t lease_epoch = 0);
  void OnCommitted(const std::weak_ptr<SessionRuntime>& weak, std::int64_t seq, bool ok, const std::string& error,
                   const std::shared_ptr<InputRecord>& input, SteadyTime received);
  void OnProgress(const std::weak_ptr<SessionRuntime>& weak, std::int64_t processed);
  void OnCheckpoint(Checkpoint checkpoint, std::int64_t lease_epoch);
  std::shared_ptr<SessionRuntime> TakeRunning(const std::string& id);
  void OnEngineFailed(const std::string& id, const std::weak_ptr<SessionRuntime>& weak, const std::string& error);
  void ReapRetired();  // under mutex_

  const ServiceOptions options_;
  StorageWriter& writer_;
  ReadPool& reads_;
  LiveSink live_sink_;
  EndSink end_sink_;
  ClusterCoordinator* cluster_ = nullptr;
  RecentFailure engine_failures_;

  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<SessionRuntime>> running_;
  std::mt19937_64 id_rng_;
  std::vector<std::thread> closers_;  // closing sessions left active at a restart
  // Failed sessions out of running_ whose engine thread may not have been joined yet.
  std::vector<std::shared_ptr<SessionRuntime>> retired_;
  std::map<std::string, std::string> failures_;  // why sessions failed since the start, by id
};

}  // namespace pslam::server
