#include "service/mapping_service.hpp"

#include <cinttypes>
#include <cstdio>
#include <iostream>

#include "cluster/cluster_coordinator.hpp"
#include "common/clock.hpp"
#include "engine/tile_codec.hpp"
#include "service/api_error.hpp"
#include "service/json_fields.hpp"
#include "service/json_views.hpp"
#include "service/extend_version.hpp"
#include "service/site_maps.hpp"
#include "storage/site_repository.hpp"

namespace pslam::server {
namespace {
constexpr int kBacklogChunk = 256;
constexpr int kSnapshotTrajectoryLimit = 1 << 20;
constexpr int kSnapshotHypothesisLimit = 10000;
constexpr std::size_t kRememberedFailures = 1024;  // for agents asking to resume a failed session
}  // namespace

MappingService::MappingService(ServiceOptions options, StorageWriter& writer, ReadPool& reads)
    : options_(std::move(options)), writer_(writer), reads_(reads), id_rng_(std::random_device{}()) {}

MappingService::~MappingService() { Shutdown(); }

void MappingService::SetLiveSinks(LiveSink live, EndSink ended) {
  live_sink_ = std::move(live);
  end_sink_ = std::move(ended);
}

std::string MappingService::NewSessionId() {
  std::lock_guard lock(mutex_);
  char id[32];
  std::snprintf(id, sizeof id, "s-%016" PRIx64, static_cast<std::uint64_t>(id_rng_()));
  return id;
}

std::shared_ptr<SessionRuntime> MappingService::Running(const std::string& id) const {
  std::lock_guard lock(mutex_);
  const auto it = running_.find(id);
  return it == running_.end() ? nullptr : it->second;
}

std::shared_ptr<SessionRuntime> MappingService::TakeRunning(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto it = running_.find(id);
  if (it == running_.end()) return nullptr;
  auto rt = it->second;
  running_.erase(it);
  return rt;
}

std::size_t MappingService::running_sessions() const {
  std::lock_guard lock(mutex_);
  return running_.size();
}

std::vector<std::string> MappingService::running_session_ids() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> ids;
  for (const auto& [id, rt] : running_) ids.push_back(id);
  return ids;
}

SiteMaps MappingService::PrepareSite(SessionSettings& settings) {
  if (settings.site.empty()) return {};
  try {
    if (settings.mode == "map") {
      {
        auto lease = reads_.Acquire();
        if (!SiteRepository(lease->repository().database()).GetSite(settings.site)) {
          throw ApiError::NotFound("no site '" + settings.site + "'");
        }
      }
      return {nullptr, LoadSiteLibrary(reads_, settings.site, kSiteLibraryVersions)};
    }
    std::int64_t version = settings.map_version;
    auto map = LoadSiteMap(reads_, settings.site, version);
    settings.map_version = version;
    settings.resolution = map->resolution();
    return {map, {}};
  } catch (const ApiError& e) {
    if (e.status() != 404) throw;
    throw ApiError::BadRequest(std::string("settings.site: ") + e.what());
  }
}

std::shared_ptr<SessionRuntime> MappingService::Launch(const SessionRow& row, const SessionSettings& settings,
                                                       const LaserGeometry& laser, std::int64_t stored_seq,
                                                       SiteMaps site_maps, std::int64_t lease_epoch) {
  auto rt = std::make_shared<SessionRuntime>();
  rt->id = row.id;
  rt->lease_epoch = lease_epoch;
  rt->source = row.source;
  rt->settings = settings;
  rt->laser = laser;
  rt->last_received = rt->last_committed = stored_seq;
  const std::weak_ptr<SessionRuntime> weak = rt;
  const std::string id = row.id;

  EngineSinks sinks;
  sinks.live = [this, id](std::shared_ptr<const LiveFrame> frame) {
    if (live_sink_) live_sink_(id, std::move(frame));
  };
  sinks.checkpoint = [this, lease_epoch](Checkpoint c) { OnCheckpoint(std::move(c), lease_epoch); };
  sinks.progress = [this, weak](std::int64_t processed) { OnProgress(weak, processed); };
  sinks.target = [weak](const ExplorationTarget& target) {
    const auto runtime = weak.lock();
    if (!runtime) return;
    std::shared_ptr<AgentLink> agent;
    {
      std::lock_guard lock(runtime->mutex);
      agent = runtime->agent.lock();
    }
    if (agent) agent->SendTarget(target);
  };
  sinks.tracking = [this, id](const TrackingChange& change) {
    std::cerr << "session " << id << ": filter " << (change.state == "ok" ? "tracking ok again" : change.state) << " at scan "
              << change.scan_index << (change.reason.empty() ? "" : ": " + change.reason) << "\n";
    if (change.state != "lost") return;
    LogEvent(id, "filter_lost",
             {{"scan_index", change.scan_index}, {"seq", change.seq}, {"t", change.t}, {"reason", change.reason}});
  };
  sinks.exploration = [this, id](const ExplorationStatus& e) {
    std::cerr << "session " << id << ": exploration " << e.state << (e.reason.empty() ? "" : " (" + e.reason + ")")
              << "; " << static_cast<int>(e.mapped_m2) << " m2 mapped, " << static_cast<int>(e.predicted_m2)
              << " m2 predicted\n";
    LogEvent(id, "exploration",
             {{"state", e.state}, {"reason", e.reason}, {"t", e.t}, {"mapped_m2", e.mapped_m2},
              {"predicted_m2", e.predicted_m2}, {"predicted_frontiers", e.predicted_frontiers}});
  };
  sinks.stuck = [this, id](const StuckReport& r) {
    std::cerr << "session " << id << ": robot stuck for " << static_cast<int>(r.seconds) << " s at (" << r.x << ", " << r.y
              << "); target (" << r.target_x << ", " << r.target_y << ") given up\n";
    LogEvent(id, "robot_stuck",
             {{"t", r.t}, {"x", r.x}, {"y", r.y}, {"target", {{"x", r.target_x}, {"y", r.target_y}}},
              {"seconds", r.seconds}});
  };
  sinks.pose_applied = [this, id](std::int64_t seq, const InitialPose& pose) {
    nlohmann::json detail = InitialPoseToJson(pose);
    detail["seq"] = seq;  // a rebuild applies it before the same input
    LogEvent(id, "initial_pose", std::move(detail));
  };
  sinks.failed = [this, id, weak](const std::string& error) { OnEngineFailed(id, weak, error); };
  sinks.rebuilt = [this, id] {
    writer_.Submit([id](SessionRepository& repo) { repo.SetRebuilds(id, 0); });
  };
  SessionSettings engine_settings = settings;
  engine_settings.plan_targets = row.source == "agent";
  rt->engine = std::make_unique<SessionEngine>(row.id, engine_settings, laser, options_.timing, std::move(sinks),
                                               std::move(site_maps));
  {
    std::lock_guard lock(mutex_);
    ReapRetired();
    running_[row.id] = rt;
  }
  BacklogReader backlog = [this, id](std::int64_t after) {
    auto lease = reads_.Acquire();
    return lease->repository().LoadInputs(id, after, kBacklogChunk);
  };
  rt->engine->Start(std::move(backlog), stored_seq, stored_seq > 0 ? LoadAppliedPoses(id) : AppliedPoses{});
  return rt;
}

AppliedPoses MappingService::LoadAppliedPoses(const std::string& id) {
  std::vector<EventRow> events;
  {
    auto lease = reads_.Acquire();
    events = lease->repository().ListEventsOfKind(id, "initial_pose");
  }
  AppliedPoses poses;
  for (const EventRow& e : events) {
    nlohmann::json detail = nlohmann::json::parse(e.detail_json, nullptr, false);
    if (!detail.is_object() || !detail.contains("seq") || !detail["seq"].is_number_integer()) continue;  // older form
    const std::int64_t seq = detail["seq"];
    detail.erase("seq");
    poses[seq] = ParseInitialPose(detail, "stored initial_pose event");
  }
  return poses;
}

// On the failed engine's thread. The failure is committed before anything else happens: until then
// the session may not take inputs, and a restart must find it failed, not rebuild it again.
void MappingService::OnEngineFailed(const std::string& id, const std::weak_ptr<SessionRuntime>& weak,
                                    const std::string& error) {
  std::cerr << "session " << id << ": engine failed: " << error << "\n";
  engine_failures_.Note("session " + id + ": " + error);
  const auto rt = weak.lock();
  std::shared_ptr<AgentLink> agent;
  if (rt) {
    std::lock_guard lock(rt->mutex);
    rt->closing = true;
    rt->agent_waiting = false;
    agent = rt->agent.lock();
    rt->agent.reset();
    rt->progress.notify_all();
  }
  try {
    writer_.Execute([&](SessionRepository& repo) {
      repo.SetFailed(id, error, UnixNow());
      repo.AddEvent(id, "engine_failed", nlohmann::json{{"error", error}}.dump(-1, ' ', false,
                                                                             nlohmann::json::error_handler_t::replace),
                    UnixNow());
    });
  } catch (const std::exception& e) {
    std::cerr << "session " << id << ": cannot record the failure: " << e.what() << "\n";
  }
  // The running slot is free again; the engine (its maps already dropped) is joined off its thread.
  {
    std::lock_guard lock(mutex_);
    const auto it = running_.find(id);
    if (it != running_.end() && it->second == rt) {
      retired_.push_back(it->second);
      running_.erase(it);
    }
    if (failures_.size() >= kRememberedFailures) failures_.erase(failures_.begin());
    failures_[id] = error;
  }
  ReleaseLease(id);
  // The filter will never catch up: an agent paused for back-pressure would wait forever.
  if (agent) agent->Disconnect("engine_failed", "the session failed (" + error + "); it is closed as failed");
  if (end_sink_) end_sink_(id, "failed");
}

void MappingService::ReapRetired() {
  std::erase_if(retired_, [](const std::shared_ptr<SessionRuntime>& rt) {
    if (!rt->engine->exited()) return false;
    rt->engine->Abort();  // joins at once: the thread has left its loop
    return true;
  });
}

void MappingService::Recover() {
  if (cluster_) return;  // a fleet node takes sessions over under their leases
  std::vector<SessionRow> rows;
  {
    auto lease = reads_.Acquire();
    for (const std::string& id : lease->repository().SessionIdsWithStatus("active")) {
      if (auto row = lease->repository().GetSession(id)) rows.push_back(std::move(*row));
    }
  }
  for (const SessionRow& row : rows) ResumeStored(row, 0);
}

std::shared_ptr<SessionRuntime> MappingService::ResumeStored(const SessionRow& row, std::int64_t lease_epoch) {
  // Start-ups in a row that died rebuilding the same stored inputs: a poison the filter cannot
  // survive. (An agent still streaming in between stores more inputs, so kills do not add up.)
  const std::int64_t attempts = row.rebuild_seq == row.last_seq ? row.rebuilds : 0;
  if (attempts >= kMaxRebuilds) {
    const std::string why = "quarantined: rebuilding its " + std::to_string(row.last_seq) + " stored inputs after a restart began " +
                            std::to_string(attempts) + " times in a row and never completed (the server died during it)";
    std::cerr << "session " << row.id << ": " << why << "\n";
    writer_.Execute([&](SessionRepository& repo) {
      repo.SetFailed(row.id, why, UnixNow());
      repo.AddEvent(row.id, "engine_failed", nlohmann::json{{"error", why}}.dump(), UnixNow());
    });
    return nullptr;
  }
  SessionSettings settings;
  LaserGeometry laser;
  SiteMaps site_maps;
  try {
    settings = ParseSessionSettings(ParseStoredJson(row.settings_json), options_.defaults, options_.limits);
    laser = ParseLaserGeometry(ParseStoredJson(row.laser_json), options_.limits);
    site_maps = PrepareSite(settings);
  } catch (const std::exception& e) {
    std::cerr << "session " << row.id << ": cannot resume (" << e.what() << "), marking it failed\n";
    writer_.Execute([&](SessionRepository& repo) {
      repo.SetFailed(row.id, std::string("cannot resume: ") + e.what(), UnixNow());
    });
    return nullptr;
  }
  // Counted before the rebuild starts, reset when it completes (or the server stops cleanly).
  if (row.last_seq > 0) {
    writer_.Execute([&](SessionRepository& repo) { repo.SetRebuilds(row.id, attempts + 1, row.last_seq); });
  }
  auto rt = Launch(row, settings, laser, row.last_seq, std::move(site_maps), lease_epoch);
  // A replay's feeder did not survive the restart: what it stored is mapped, then the session
  // closes. An agent's session waits for the agent to reconnect, unless told otherwise.
  const bool close = row.source == "replay" || !options_.resume_on_restart;
  LogEvent(row.id, close ? "closing_after_restart" : "resumed_after_restart", {{"inputs", row.last_seq}});
  std::cerr << "session " << row.id << ": rebuilding from " << row.last_seq << " stored inputs"
            << (close ? ", then closing" : "") << "\n";
  if (close) {
    if (row.source == "replay") {
      writer_.Submit([id = row.id](SessionRepository& repo) { repo.SetMetrics(id, R"({"interrupted":true})"); });
    }
    std::lock_guard lock(mutex_);
    closers_.emplace_back([this, id = row.id] {
      try {
        CloseSession(id);
      } catch (const std::exception& e) {
        std::cerr << "session " << id << ": closing after restart failed: " << e.what() << "\n";
      }
    });
  }
  return rt;
}

void MappingService::Shutdown() {
  std::vector<std::thread> closers;
  {
    std::lock_guard lock(mutex_);
    closers.swap(closers_);
  }
  for (auto& t : closers) t.join();
  std::map<std::string, std::shared_ptr<SessionRuntime>> running;
  {
    std::lock_guard lock(mutex_);
    running.swap(running_);
  }
  for (auto& [id, rt] : running) {
    {
      std::lock_guard lock(rt->mutex);
      rt->closing = true;
      rt->progress.notify_all();
    }
    rt->engine->Stop();  // checkpoints; the session stays active and resumes at the next start
    // A clean stop, even in the middle of a rebuild, is no reason to quarantine the session.
    if (!rt->engine->failed()) writer_.Submit([id = id](SessionRepository& repo) { repo.SetRebuilds(id, 0); });
  }
  std::vector<std::shared_ptr<SessionRuntime>> retired;
  {
    std::lock_guard lock(mutex_);
    retired.swap(retired_);
  }
  for (auto& rt : retired) rt->engine->Abort();
}

void MappingService::OpenForAgent(const HelloMessage& hello, const std::shared_ptr<AgentLink>& link,
                                  std::function<void(AgentOpen)> done) {
  if (hello.session != "new") {
    if (const auto rt = Running(hello.session)) return AttachAgent(rt, hello, link, done);
    if (!cluster_) return done(AgentOpen::Failed(UnknownSession(hello.session)));
    cluster_->Post([this, hello, link, done](ClusterCoordinator&) { ClaimForAgent(hello, link, done); });
    return;
  }
  // A new session goes to the least loaded node, once: a redirected agent is placed where it went.
  if (cluster_ && !hello.redirected) {
    cluster_->Post([this, hello, link, done](ClusterCoordinator& cluster) {
      const Placement placement = cluster.PlaceNew();
      if (placement.kind == Placement::Kind::kElsewhere) return done(AgentOpen::Redirect(placement.address));
      if (placement.kind == Placement::Kind::kUnavailable) {
        return done(AgentOpen::Failed(IngestError{"overloaded", placement.reason}));
      }
      CreateForAgent(hello, link, done);
    });
    return;
  }
  CreateForAgent(hello, link, done);
}

IngestError MappingService::UnknownSession(const std::string& id) {
  std::string why = " is not active";
  {
    std::lock_guard lock(mutex_);
    if (const auto it = failures_.find(id); it != failures_.end()) why = " has failed: " + it->second;
  }
  return IngestError{"unknown_session", "session '" + id.substr(0, 64) + "'" + why};
}

void MappingService::AttachAgent(const std::shared_ptr<SessionRuntime>& rt, const HelloMessage& hello,
                                 const std::shared_ptr<AgentLink>& link, const std::function<void(AgentOpen)>& done) {
  if (hello.laser && hello.laser->beams != rt->laser.beams) {
    done(AgentOpen::Failed(IngestError{"bad_message", "hello: the session's laser has " + std::to_string(rt->laser.beams) +
                                                      " beams, not " + std::to_string(hello.laser->beams)}));
    return;
  }
  std::shared_ptr<AgentLink> previous;
  std::int64_t acked = 0;
  {
    std::lock_guard lock(rt->mutex);
    if (rt->closing) {
      const std::string why = rt->engine->failed() ? " has failed (its events say why)" : " is closing";
      done(AgentOpen::Failed(IngestError{"unknown_session", "session " + rt->id + why}));
      return;
    }
    previous = rt->agent.lock();
    rt->agent = link;
    rt->agent_waiting = false;
    acked = rt->last_committed;
  }
  if (previous && previous != link) previous->Disconnect("replaced", "a newer connection of the agent took the session");
  LogEvent(rt->id, "agent_connected", {{"robot_id", hello.robot_id}, {"resumed", true}, {"last_acked_seq", acked}});
  done(AgentOpen::Opened(rt, acked));
}

void MappingService::ClaimForAgent(const HelloMessage& hello, const std::shared_ptr<AgentLink>& link,
                                   std::function<void(AgentOpen)> done) {
  try {
    if (GetSession(hello.session).status != "active") return done(AgentOpen::Failed(UnknownSession(hello.session)));
  } catch (const ApiError&) {
    return done(AgentOpen::Failed(UnknownSession(hello.session)));
  }
  const Placement placement = cluster_->Claim(hello.session);
  if (placement.kind == Placement::Kind::kElsewhere) return done(AgentOpen::Redirect(placement.address));
  if (placement.kind == Placement::Kind::kUnavailable) {
    return done(AgentOpen::Failed(IngestError{"session_moving", "session " + hello.session + ": " + placement.reason}));
  }
  auto rt = Running(hello.session);
  if (!rt) {
    // Read again under the lease: the inputs the previous owner stored are all in now.
    const SessionRow row = GetSession(hello.session);
    if (row.status == "active") rt = ResumeStored(row, placement.epoch);
  }
  if (!rt) {
    ReleaseLease(hello.session);
    return done(AgentOpen::Failed(UnknownSession(hello.session)));
  }
  AttachAgent(rt, hello, link, done);
}

void MappingService::Adopt(const std::string& id, std::int64_t lease_epoch) {
  try {
    const SessionRow row = GetSession(id);
    if (row.status == "active" && !Running(id) && ResumeStored(row, lease_epoch)) return;
  } catch (const std::exception& e) {
    std::cerr << "session " << id << ": taking it over failed: " << e.what() << "\n";
  }
  if (!Running(id)) ReleaseLease(id);
}

void MappingService::Abandon(const std::string& id) {
  const auto rt = TakeRunning(id);
  if (!rt) return;
  // The agent reconnects and is sent to the new owner, which resends it every unacknowledged
  // input; no checkpoint: the new owner writes the session from here on.
  StopWithoutCheckpoint(*rt, "moved", "another node runs the session now; reconnect");
  LogEvent(id, "lease_lost", {});
  if (end_sink_) end_sink_(id, "moved");
}

bool MappingService::HandOver(const std::string& id) {
  const auto rt = TakeRunning(id);
  if (!rt) return false;
  std::shared_ptr<AgentLink> agent;
  {
    std::lock_guard lock(rt->mutex);
    rt->closing = true;
    agent = rt->agent.lock();
    rt->agent.reset();
    rt->progress.notify_all();
  }
  rt->engine->Stop();  // after its current input, with a checkpoint, as at a shutdown
  if (!rt->engine->failed()) writer_.Submit([id](SessionRepository& repo) { repo.SetRebuilds(id, 0); });
  writer_.Execute([](SessionRepository&) {});  // all of it committed while the lease is still ours
  LogEvent(id, "handed_over", {});
  // Its reconnect is sent to the node taking it; unacknowledged inputs are resent there.
  if (agent) agent->Disconnect("moved", "the session moves to a less loaded node; reconnect");
  if (end_sink_) end_sink_(id, "moved");
  return true;
}

void MappingService::StopWithoutCheckpoint(SessionRuntime& rt, const std::string& code, const std::string& why) {
  std::shared_ptr<AgentLink> agent;
  {
    std::lock_guard lock(rt.mutex);
    rt.closing = true;
    agent = rt.agent.lock();
    rt.agent.reset();
    rt.progress.notify_all();
  }
  if (agent) agent->Disconnect(code, why);
  rt.engine->Abort();
}

void MappingService::ReleaseLease(const std::string& id) {
  if (cluster_) cluster_->Released(id);
}

void MappingService::ThrowIfElsewhere(const std::string& id) {
  if (!cluster_) return;
  if (const auto address = cluster_->OwnerElsewhere(id)) {
    throw ApiError::Elsewhere(*address, "session " + id + " runs on the node at " + *address);
  }
}

void MappingService::CreateForAgent(const HelloMessage& hello, const std::shared_ptr<AgentLink>& link,
                                    std::function<void(AgentOpen)> done) {
  if (running_sessions() >= options_.max_running_sessions) {
    done(AgentOpen::Failed(IngestError{"overloaded", "the server runs its maximum of sessions"}));
    return;
  }
  SessionSettings settings;
  SiteMaps site_maps;
  try {
    settings = ParseSessionSettings(hello.settings, options_.defaults, options_.limits, "hello.settings");
    site_maps = PrepareSite(settings);
  } catch (const ApiError& e) {
    done(AgentOpen::Failed(IngestError{"bad_message", e.what()}));
    return;
  }
  SessionRow row;
  row.id = NewSessionId();
  row.name = hello.session_name;
  row.robot_id = hello.robot_id;
  row.source = "agent";
  row.created_at = row.updated_at = UnixNow();
  row.laser_json = LaserGeometryToJson(*hello.laser).dump();
  row.settings_json = SessionSettingsToJson(settings).dump();
  const LaserGeometry laser = *hello.laser;
  auto epoch = std::make_shared<std::int64_t>(0);
  const bool queued = writer_.Submit(
      [row, epoch, cluster = cluster_](SessionRepository& repo) {
        repo.CreateSession(row);
        if (cluster) *epoch = cluster->AcquireIn(repo.database(), row.id);
        repo.AddEvent(row.id, "created", nlohmann::json{{"source", "agent"}, {"robot_id", row.robot_id}}.dump(),
                      row.created_at);
      },
      [this, row, settings, laser, link, done, site_maps, epoch](bool ok, const std::string& error) {
        if (!ok) {
          done(AgentOpen::Failed(IngestError{"storage_error", "cannot create the session: " + error}));
          return;
        }
        auto rt = Launch(row, settings, laser, 0, site_maps, *epoch);
        {
          std::lock_guard lock(rt->mutex);
          rt->agent = link;
        }
        done(AgentOpen::Opened(rt, 0));
      });
  if (!queued) done(AgentOpen::Failed(IngestError{"overloaded", "the server is shutting down"}));
}

MappingService::AdmitResult MappingService::Admit(const std::shared_ptr<SessionRuntime>& rt, const AgentLink* link,
                                                  InputRecord input) {
  std::lock_guard lock(rt->mutex);
  AdmitResult result;
  result.committed_seq = rt->last_committed;
  result.expected_seq = rt->last_received + 1;
  if (rt->closing) {
    result.admission = Admission::kClosed;
    return result;
  }
  if (link && rt->agent.lock().get() != link) {
    result.admission = Admission::kNotOwner;
    return result;
  }
  if (input.seq <= rt->last_received) {
    result.admission = Admission::kDuplicate;
    return result;
  }
  if (input.seq != rt->last_received + 1) {
    result.admission = Admission::kOutOfOrder;
    return result;
  }
  if (rt->last_pose) {
    result.problem = PoseJumpProblem(*rt->last_pose, input);
    if (!result.problem.empty()) {
      result.admission = Admission::kImplausible;
      return result;
    }
  }
  const std::int64_t seq = input.seq;
  auto shared = std::make_shared<InputRecord>(std::move(input));
  const SteadyTime received = SteadyNow();
  const std::weak_ptr<SessionRuntime> weak = rt;
  // Submitted under the runtime's lock, so inputs reach the writer in seq order even if a newer
  // connection of the agent takes over at this moment.
  const bool queued = writer_.Submit(
      [id = rt->id, shared, epoch = rt->lease_epoch, cluster = cluster_](SessionRepository& repo) {
        if (cluster) return cluster->InsertInputIn(repo, id, epoch, *shared);
        repo.InsertInput(id, *shared);
      },
      [this, weak, seq, shared, received](bool ok, const std::string& error) {
        OnCommitted(weak, seq, ok, error, shared, received);
      });
  if (!queued) {
    result.admission = Admission::kClosed;
    return result;
  }
  rt->last_received = seq;
  InputRecord pose;  // what the session's view needs of the input: no ranges
  pose.seq = seq;
  pose.kind = shared->kind;
  pose.t = shared->t;
  pose.x = shared->x;
  pose.y = shared->y;
  rt->last_pose = std::move(pose);
  result.expected_seq = seq + 1;
  return result;
}

void MappingService::OnCommitted(const std::weak_ptr<SessionRuntime>& weak, std::int64_t seq, bool ok,
                                 const std::string& error, const std::shared_ptr<InputRecord>& input,
                                 SteadyTime received) {
  const auto rt = weak.lock();
  if (!rt) return;
  std::shared_ptr<AgentLink> agent;
  {
    std::lock_guard lock(rt->mutex);
    agent = rt->agent.lock();
    if (!ok) {
      // Forget what was admitted after the last commit: the agent's resend of it is admitted
      // again (inputs that did commit meanwhile are ignored by InsertInput then).
      rt->last_received = rt->last_committed;
    } else if (seq != rt->last_committed + 1) {
      return;  // an earlier input failed to commit; this one waits for the resend
    } else {
      rt->last_committed = seq;
    }
  }
  if (!ok) {
    std::cerr << "session " << rt->id << ": storing input " << seq << " failed: " << error << "\n";
    if (agent) agent->Disconnect("storage_error", "storing input " + std::to_string(seq) + " failed; resend after reconnecting");
    return;
  }
  rt->engine->Push(std::move(*input), received);
  if (agent) agent->SendAck(seq);
}

void MappingService::OnProgress(const std::weak_ptr<SessionRuntime>& weak, std::int64_t processed) {
  const auto rt = weak.lock();
  if (!rt) return;
  std::shared_ptr<AgentLink> agent;
  {
    std::lock_guard lock(rt->mutex);
    rt->progress.notify_all();
    if (!rt->agent_waiting || rt->last_received - processed > options_.max_inflight / 2) return;
    rt->agent_waiting = false;
    agent = rt->agent.lock();
  }
  if (agent) agent->Resume();
}

bool MappingService::PauseIfOverloaded(const std::shared_ptr<SessionRuntime>& rt) {
  std::lock_guard lock(rt->mutex);
  if (rt->last_received - rt->engine->processed_seq() <= options_.max_inflight) return false;
  rt->agent_waiting = true;
  return true;
}

void MappingService::WaitForRoom(const std::shared_ptr<SessionRuntime>& rt) {
  std::unique_lock lock(rt->mutex);
  while (!rt->closing && !rt->engine->failed() &&
         rt->last_received - rt->engine->processed_seq() >= options_.max_inflight) {
    rt->progress.wait_for(lock, std::chrono::milliseconds(200));
  }
}

void MappingService::Detach(const std::shared_ptr<SessionRuntime>& rt, const AgentLink* link) {
  {
    std::lock_guard lock(rt->mutex);
    if (rt->agent.lock().get() != link) return;
    rt->agent.reset();
    rt->agent_waiting = false;
  }
  LogEvent(rt->id, "agent_disconnected", nlohmann::json::object());
}

void MappingService::OnCheckpoint(Checkpoint c, std::int64_t lease_epoch) {
  c.stats_json = EngineStatsToJson(c.stats).dump();
  const double now = UnixNow();
  writer_.Submit([c = std::move(c), now, lease_epoch, cluster = cluster_](SessionRepository& repo) {
                   if (cluster) cluster->CheckLeaseIn(repo.database(), c.session_id, lease_epoch);
                   repo.WriteCheckpoint(c, now);
                 },
                 [](bool ok, const std::string& error) {
                   if (!ok) std::cerr << "storage: checkpoint failed: " << error << "\n";
                 });
}

SessionRow MappingService::CreateSession(const nlohmann::json& body) {
  JsonFields f(body, "session");
  SessionRow row;
  row.name = f.String("name").value_or("");
  row.robot_id = f.String("robot_id", 128).value_or("");
  const nlohmann::json* laser_json = f.Object("laser");
  if (!laser_json) f.Fail("laser", "is required");
  const LaserGeometry laser = ParseLaserGeometry(*laser_json, options_.limits, "session.laser");
  const nlohmann::json* settings_json = f.Object("settings");
  const SessionSettings settings = ParseSessionSettings(settings_json ? *settings_json : nlohmann::json(),
                                                        options_.defaults, options_.limits, "session.settings");
  f.RejectUnknown();
  row.source = "api";
  const auto rt = StartSession(row, settings, laser);
  return GetSession(rt->id);
}

std::shared_ptr<SessionRuntime> MappingService::StartSession(SessionRow row, const SessionSettings& requested,
                                                             const LaserGeometry& laser) {
  if (running_sessions() >= options_.max_running_sessions) {
    throw ApiError::Unavailable("the server runs its maximum of " + std::to_string(options_.max_running_sessions) +
                                " sessions");
  }
  SessionSettings settings = requested;
  SiteMaps site_maps = PrepareSite(settings);
  if (row.id.empty()) row.id = NewSessionId();
  row.status = "active";
  row.created_at = row.updated_at = UnixNow();
  row.laser_json = LaserGeometryToJson(laser).dump();
  row.settings_json = SessionSettingsToJson(settings).dump();
  std::int64_t epoch = 0;
  writer_.Execute([&](SessionRepository& repo) {
    repo.CreateSession(row);
    if (cluster_) epoch = cluster_->AcquireIn(repo.database(), row.id);
    repo.AddEvent(row.id, "created", nlohmann::json{{"source", row.source}}.dump(), row.created_at);
  });
  return Launch(row, settings, laser, 0, std::move(site_maps), epoch);
}

SessionRow MappingService::GetSession(const std::string& id) {
  auto lease = reads_.Acquire();
  auto row = lease->repository().GetSession(id);
  if (!row) throw ApiError::NotFound("no session '" + id.substr(0, 64) + "'");
  return *row;
}

SessionPage MappingService::ListSessions(const SessionFilter& filter) {
  auto lease = reads_.Acquire();
  return lease->repository().ListSessions(filter);
}

SessionRow MappingService::CloseSession(const std::string& id, const std::string& status) {
  const auto rt = Running(id);
  if (!rt) {
    SessionRow row = GetSession(id);
    if (row.status != "active") return row;  // closing twice is not an error
    ThrowIfElsewhere(id);
    writer_.Execute([&](SessionRepository& repo) { repo.SetStatus(id, status, UnixNow()); });
    return GetSession(id);
  }
  std::shared_ptr<AgentLink> agent;
  {
    std::lock_guard lock(rt->mutex);
    if (rt->closing && rt->engine->failed()) return GetSession(id);  // failed: nothing left to close
    if (rt->closing) throw ApiError::Conflict("session " + id + " is already closing");
    rt->closing = true;
    agent = rt->agent.lock();
    rt->agent.reset();
    rt->progress.notify_all();
  }
  if (agent) agent->Disconnect("closed", "the session was closed");
  // Inputs admitted before the close are committed and queued for the engine first (the writer
  // runs jobs in order), then the engine drains, then its final checkpoint precedes the status.
  writer_.Execute([](SessionRepository&) {});
  rt->engine->Finish();
  if (rt->engine->failed()) return GetSession(id);  // failed while draining: recorded as such
  const std::optional<SiteMapRow> extended = ExtendedSiteMap(*rt);
  std::int64_t version = 0;
  writer_.Execute([&](SessionRepository& repo) {
    repo.SetStatus(id, status, UnixNow());
    repo.AddEvent(id, "closed", nlohmann::json{{"status", status}}.dump(), UnixNow());
    // In the same transaction: a closed extend session always left its version.
    if (extended) version = SiteRepository(repo.database()).AddMapVersion(*extended);
  });
  if (extended) {
    LogEvent(std::nullopt, "site_map_added",
             {{"site_id", extended->site_id}, {"version", version}, {"source", "session"}, {"session_id", id},
              {"extends_version", *extended->extends_version}});
  } else if (rt->settings.mode == "extend") {
    LogEvent(id, "site_map_not_extended", {{"reason", "the session never localized on the site's map"}});
  }
  TakeRunning(id);
  ReleaseLease(id);
  if (end_sink_) end_sink_(id, status);
  return GetSession(id);
}

void MappingService::DeleteSession(const std::string& id) {
  if (const auto rt = TakeRunning(id)) {
    StopWithoutCheckpoint(*rt, "closed", "the session was deleted");
    ReleaseLease(id);
  } else {
    ThrowIfElsewhere(id);
  }
  bool deleted = false;
  writer_.Execute([&](SessionRepository& repo) { deleted = repo.DeleteSession(id); });
  if (end_sink_) end_sink_(id, "deleted");
  if (!deleted) throw ApiError::NotFound("no session '" + id.substr(0, 64) + "'");
}

bool MappingService::SetVerifyPredicted(const std::string& id, bool verify) {
  const SessionRow row = GetSession(id);
  const auto rt = Running(id);
  if (!rt) ThrowIfElsewhere(id);
  if (!rt) throw ApiError::Conflict("session " + id + " is " + row.status + ": it explores no more");
  if (row.source != "agent") throw ApiError::Conflict("session " + id + " has no robot to drive (source " + row.source + ")");
  if (rt->engine->verify_predicted() != verify) {
    rt->engine->SetVerifyPredicted(verify);
    LogEvent(id, "verify_predictions", {{"verify", verify}});
  }
  return verify;
}

InitialPose MappingService::SetInitialPose(const std::string& id, const nlohmann::json& body) {
  const SessionRow row = GetSession(id);
  const InitialPose pose = ParseInitialPose(body, "initial_pose");
  const auto rt = Running(id);
  if (!rt) ThrowIfElsewhere(id);
  if (!rt) throw ApiError::Conflict("session " + id + " is " + row.status + ": it localizes no more");
  if (rt->settings.mode == "map") {
    throw ApiError::Conflict("session " + id + " maps (mode \"map\"): only a localize or extend session takes a pose");
  }
  rt->engine->SetInitialPose(pose);  // logged when applied, with the input it is applied before
  return pose;
}

nlohmann::json MappingService::Statistics(const std::string& id) {
  SessionRow row = GetSession(id);
  HypothesisCounts counts;
  {
    auto lease = reads_.Acquire();
    counts = lease->repository().CountHypotheses(id);
  }
  nlohmann::json out = {{"session_id", id}, {"status", row.status}};
  const auto rt = Running(id);
  out["running"] = rt != nullptr;
  std::int64_t acked = row.last_seq, received = row.last_seq;
  if (rt) {
    out["filter"] = EngineStatsToJson(rt->engine->stats());
    std::lock_guard lock(rt->mutex);
    acked = rt->last_committed;
    received = rt->last_received;
  } else {
    out["filter"] = ParseStoredJson(row.stats_json);
  }
  out["ingest"] = {{"received_seq", received}, {"acked_seq", acked}};
  out["predictions"] = HypothesisCountsToJson(counts);
  out["metrics"] = ParseStoredJson(row.metrics_json);
  const WriterStats w = writer_.stats();
  out["storage"] = {{"commits", w.commits},
                    {"jobs", w.jobs},
                    {"last_commit_ms", w.last_commit_ms},
                    {"max_commit_ms", w.max_commit_ms},
                    {"queued", writer_.queued()}};
  return out;
}

MapView MappingService::CurrentMap(const std::string& id) {
  if (const auto rt = Running(id)) {
    const auto frame = rt->engine->latest_frame();
    return {frame ? frame->map : nullptr, rt->settings.resolution, true};
  }
  const SessionRow row = GetSession(id);
  const nlohmann::json settings = ParseStoredJson(row.settings_json);
  const double resolution = settings.value("resolution_meters", options_.defaults.resolution);
  std::vector<TileRow> tiles;
  {
    auto lease = reads_.Acquire();
    tiles = lease->repository().LoadTiles(id);
  }
  if (tiles.empty()) return {nullptr, resolution, false};
  return {std::make_shared<const OccupancyGrid>(GridFromTiles(tiles, resolution)), resolution, false};
}

std::vector<LiveMessage> MappingService::StoredLiveSnapshot(const std::string& id) {
  const SessionRow row = GetSession(id);
  const nlohmann::json settings = ParseStoredJson(row.settings_json);
  const double resolution = settings.value("resolution_meters", options_.defaults.resolution);
  auto lease = reads_.Acquire();
  SessionRepository& repo = lease->repository();
  HypothesisFilter all;
  all.limit = kSnapshotHypothesisLimit;
  return pslam::server::StoredSnapshot(id, row.status, resolution, repo.LoadTiles(id),
                                       repo.LoadTrajectory(id, 0, kSnapshotTrajectoryLimit),
                                       repo.QueryHypotheses(id, all).hypotheses, ParseStoredJson(row.stats_json));
}

void MappingService::LogEvent(const std::optional<std::string>& session_id, const std::string& kind,
                              nlohmann::json detail) {
  const std::string text = detail.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  const double now = UnixNow();
  writer_.Submit([session_id, kind, text, now](SessionRepository& repo) { repo.AddEvent(session_id, kind, text, now); });
}

}  // namespace pslam::server
