#include "service/replay_service.hpp"

#include <chrono>
#include <cstdio>
#include <iostream>

#include "common/clock.hpp"
#include "pslam/eval/map_divergence.hpp"
#include "pslam/eval/relative_pose_error.hpp"
#include "pslam/io/carmen_reader.hpp"
#include "pslam/io/map_io.hpp"
#include "service/api_error.hpp"
#include "service/json_fields.hpp"
#include "service/json_views.hpp"

namespace pslam::server {
namespace {
constexpr int kInputChunk = 256;
constexpr double kMaxSpeed = 1000.0;
constexpr const char* kNoReplayDir = "this server has no replay directory (--replay-dir); it replays stored sessions only";
}  // namespace

struct ReplayService::Plan {
  std::shared_ptr<SessionRuntime> runtime;
  std::optional<std::string> source_session;
  std::optional<std::filesystem::path> log;
  std::optional<LaserScan> first_scan;             // logs: read while validating, fed first
  std::unique_ptr<CarmenReader> reader;
  std::unique_ptr<ScanStream> scans;
  double speed = 0.0;                              // 0: as fast as possible
  std::optional<std::filesystem::path> relations;
  std::optional<std::filesystem::path> reference_map;
  SteadyTime wall_start{};
  std::optional<double> first_time;
  std::int64_t fed = 0;
  std::int64_t skipped = 0;
};

ReplayService::ReplayService(MappingService& mapping, std::optional<std::filesystem::path> replay_dir)
    : mapping_(mapping), replay_dir_(std::move(replay_dir)) {}

ReplayService::~ReplayService() { Shutdown(); }

void ReplayService::Shutdown() {
  stopping_ = true;
  std::vector<std::thread> feeders;
  {
    std::lock_guard lock(mutex_);
    feeders.swap(feeders_);
  }
  for (auto& t : feeders) t.join();
}

std::vector<ReplayFile> ReplayService::Files() const {
  if (!replay_dir_) throw ApiError::Forbidden(kNoReplayDir);
  try {
    return ListReplayFiles(*replay_dir_);
  } catch (const std::filesystem::filesystem_error&) {
    throw ApiError::Unavailable("the replay directory is not accessible");
  }
}

std::filesystem::path ReplayService::ResolveInside(const std::filesystem::path& root, const std::string& relative) {
  namespace fs = std::filesystem;
  const fs::path rel(relative);
  if (relative.empty() || rel.is_absolute() || relative.find('\0') != std::string::npos) {
    throw ApiError::BadRequest("paths are relative to the server's replay directory");
  }
  std::error_code ec;
  const fs::path base = fs::canonical(root, ec);
  if (ec) throw ApiError::Unavailable("the replay directory is not accessible");
  // canonical() resolves '..' and symbolic links, so the prefix test below sees where the file
  // really is.
  const fs::path full = fs::weakly_canonical(base / rel, ec);
  if (ec) throw ApiError::BadRequest("invalid path '" + relative.substr(0, 128) + "'");
  const auto [root_end, unused] = std::mismatch(base.begin(), base.end(), full.begin(), full.end());
  if (root_end != base.end() || full == base) {
    throw ApiError::BadRequest("path '" + relative.substr(0, 128) + "' is outside the replay directory");
  }
  if (!fs::is_regular_file(full, ec)) throw ApiError::NotFound("no file '" + relative.substr(0, 128) + "'");
  return full;
}

SessionRow ReplayService::Start(const nlohmann::json& body) {
  if (stopping_) throw ApiError::Unavailable("the server is shutting down");
  JsonFields f(body, "replay");
  auto plan = std::make_shared<Plan>();
  plan->source_session = f.String("session", 64);
  const auto log = f.String("log", 1024);
  const auto relations = f.String("relations", 1024);
  const auto reference_map = f.String("reference_map", 1024);
  const auto name = f.String("name");
  plan->speed = f.NumberOr("speed", 0.0);
  const nlohmann::json* settings_json = f.Object("settings");
  f.RejectUnknown();
  if (plan->speed < 0.0 || plan->speed > kMaxSpeed) f.Fail("speed", "must be in [0, 1000] (0: as fast as possible)");
  if (plan->source_session.has_value() == log.has_value()) {
    throw ApiError::BadRequest("replay needs exactly one of 'session' (a stored session) and 'log' (a CARMEN log)");
  }
  if ((log || relations || reference_map) && !replay_dir_) {
    throw ApiError::Forbidden(kNoReplayDir);
  }
  if (relations) plan->relations = ResolveInside(*replay_dir_, *relations);
  if (reference_map) plan->reference_map = ResolveInside(*replay_dir_, *reference_map);

  SessionSettings defaults = mapping_.options().defaults;
  LaserGeometry laser;
  SessionRow row;
  row.source = "replay";
  if (plan->source_session) {
    const SessionRow source = mapping_.GetSession(*plan->source_session);
    defaults = ParseSessionSettings(ParseStoredJson(source.settings_json), defaults, mapping_.options().limits);
    laser = ParseLaserGeometry(ParseStoredJson(source.laser_json), mapping_.options().limits);
    row.replay_of = source.id;
    row.robot_id = source.robot_id;
    row.name = name.value_or("replay of " + (source.name.empty() ? source.id : source.name));
  } else {
    plan->log = ResolveInside(*replay_dir_, *log);
    try {
      plan->reader = std::make_unique<CarmenReader>(plan->log->string());
      plan->scans = std::make_unique<ScanStream>(*plan->reader);
      plan->first_scan = plan->scans->Next();
    } catch (const std::exception& e) {
      throw ApiError::BadRequest(std::string("cannot read the log: ") + e.what());
    }
    if (!plan->first_scan) throw ApiError::BadRequest("the log has no laser scans");
    const LaserScan& s = *plan->first_scan;
    laser.angle_min = s.angle_min;
    laser.angle_increment = s.angle_increment;
    laser.beams = static_cast<int>(s.ranges.size());
    laser.max_range = s.max_range;
    laser.min_range = s.min_range;
    laser.offset_x = s.sensor_offset.x;
    laser.offset_y = s.sensor_offset.y;
    laser.offset_theta = s.sensor_offset.theta;
    row.replay_of = *log;
    row.name = name.value_or("replay of " + *log);
  }
  const SessionSettings settings = ParseSessionSettings(settings_json ? *settings_json : nlohmann::json(), defaults,
                                                        mapping_.options().limits, "replay.settings");
  plan->runtime = mapping_.StartSession(row, settings, laser);
  const std::string id = plan->runtime->id;
  mapping_.LogEvent(id, "replay_started",
                    {{"replay_of", *row.replay_of}, {"speed", plan->speed}, {"seed", settings.seed},
                     {"particles", settings.particles}});
  {
    std::lock_guard lock(mutex_);
    feeders_.emplace_back([this, plan] { Feed(plan); });
  }
  return mapping_.GetSession(id);
}

bool ReplayService::Pace(Plan& plan, double t) {
  if (!plan.first_time) {
    plan.first_time = t;
    plan.wall_start = SteadyNow();
  }
  if (plan.speed > 0.0) {
    const double offset = std::max(0.0, (t - *plan.first_time) / plan.speed);
    const auto due = plan.wall_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                           std::chrono::duration<double>(offset));
    while (!stopping_ && SteadyNow() < due) {
      std::this_thread::sleep_until(std::min(due, SteadyNow() + std::chrono::milliseconds(100)));
    }
  }
  mapping_.WaitForRoom(plan.runtime);
  return !stopping_;
}

void ReplayService::FeedStoredSession(Plan& plan) {
  std::int64_t after = 0;
  for (;;) {
    std::vector<InputRecord> chunk;
    {
      auto lease = mapping_.reads().Acquire();
      chunk = lease->repository().LoadInputs(*plan.source_session, after, kInputChunk);
    }
    if (chunk.empty()) return;
    for (InputRecord& input : chunk) {
      after = input.seq;
      if (!Pace(plan, input.t)) return;
      input.seq = ++plan.fed;  // renumbered: a gap in the source must not stall the replay
      if (mapping_.Admit(plan.runtime, nullptr, std::move(input)).admission != MappingService::Admission::kAccepted) {
        return;
      }
    }
  }
}

void ReplayService::FeedCarmenLog(Plan& plan) {
  std::optional<LaserScan> scan = std::move(plan.first_scan);
  const std::size_t beams = scan ? scan->ranges.size() : 0;
  for (; scan; scan = plan.scans->Next()) {
    if (scan->ranges.size() != beams) {  // a second laser or a corrupt line: not this session's laser
      ++plan.skipped;
      continue;
    }
    if (!Pace(plan, scan->timestamp)) return;
    InputRecord input;
    input.seq = ++plan.fed;
    input.kind = InputKind::kScan;
    input.t = scan->timestamp;
    input.stamp = scan->timestamp_text;
    input.x = scan->odometry.x;
    input.y = scan->odometry.y;
    input.theta = scan->odometry.theta;
    input.ranges = std::move(scan->ranges);
    const auto admission = mapping_.Admit(plan.runtime, nullptr, std::move(input)).admission;
    if (admission == MappingService::Admission::kImplausible) {  // an odometry glitch of the log: skip the scan
      --plan.fed;
      ++plan.skipped;
      continue;
    }
    if (admission != MappingService::Admission::kAccepted) return;
  }
}

void ReplayService::Feed(std::shared_ptr<Plan> plan) {
  const std::string id = plan->runtime->id;
  try {
    if (plan->source_session) {
      FeedStoredSession(*plan);
    } else {
      FeedCarmenLog(*plan);
    }
    if (stopping_) return;  // the session stays active and is closed after the next start
    mapping_.CloseSession(id);
    ComputeMetrics(*plan);
    mapping_.LogEvent(id, "replay_finished", {{"inputs", plan->fed}, {"skipped", plan->skipped}});
  } catch (const std::exception& e) {
    // A deleted session or a failed engine ends the replay; nothing else to clean up.
    std::cerr << "replay " << id << ": " << e.what() << "\n";
    mapping_.LogEvent(id, "replay_failed", {{"error", e.what()}});
  }
}

void ReplayService::ComputeMetrics(const Plan& plan) {
  if (!plan.relations && !plan.reference_map) return;
  const std::string id = plan.runtime->id;
  nlohmann::json metrics = nlohmann::json::object();
  try {
    if (plan.relations) {
      std::vector<TrajectoryRow> rows;
      {
        auto lease = mapping_.reads().Acquire();
        rows = lease->repository().LoadTrajectory(id, 0, 1 << 24);
      }
      std::vector<StampedPose> trajectory;
      trajectory.reserve(rows.size());
      for (const TrajectoryRow& r : rows) {
        char text[64];
        std::snprintf(text, sizeof text, "%.6f", r.t);
        trajectory.push_back({r.stamp.empty() ? std::string(text) : r.stamp, r.t, Pose2D(r.x, r.y, r.theta)});
      }
      const RpeResult rpe = ComputeRpe(trajectory, ReadRelations(plan.relations->string()));
      metrics["rpe"] = {{"used", rpe.used},
                        {"missing", rpe.missing},
                        {"trans_mean_m", rpe.trans_mean},
                        {"trans_std_m", rpe.trans_std},
                        {"rot_mean_deg", rpe.rot_mean_deg},
                        {"rot_std_deg", rpe.rot_std_deg},
                        {"trans_max_m", rpe.trans_max},
                        {"rot_max_deg", rpe.rot_max_deg}};
    }
    if (plan.reference_map) {
      const OccupancyGrid reference = LoadMap(plan.reference_map->string());
      const MapView map = mapping_.CurrentMap(id);
      const MapDivergence kl = ComputeMapDivergence(reference, map.grid ? *map.grid : OccupancyGrid(map.resolution));
      metrics["kl"] = {{"nats", kl.kl}, {"cells", kl.cells}};
    }
  } catch (const std::exception& e) {
    metrics["error"] = e.what();
  }
  mapping_.writer().Execute([&](SessionRepository& repo) { repo.SetMetrics(id, metrics.dump()); });
}

}  // namespace pslam::server
