#include "agent.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <thread>

#include "common/clock.hpp"
#include "common/log.hpp"
#include "drive/path_frames.hpp"
#include "link/messages.hpp"
#include "link/session_closer.hpp"
#include "link/session_state.hpp"

namespace pslam::agent {
namespace {

constexpr double kPollSeconds = 0.05;
constexpr double kDrivePeriodSeconds = 0.1;        // the controller runs at the SIP rate
constexpr double kSpoolFullReportPeriod = 10.0;
constexpr double kCloseTimeoutSeconds = 30.0;  // the server drains the filter before it answers
constexpr double kSameTargetMetres = 0.05;
constexpr double kFinalAckWaitSeconds = 10.0;  // closing: how long the server may take to acknowledge the rest

ScanMessage ToMessage(const LaserScan& scan) {
  ScanMessage m;
  m.t = scan.timestamp;
  m.odom = scan.odometry;
  m.ranges.resize(scan.ranges.size());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    // The wire marks "no return" explicitly; max-range readings and invalid values are not hits.
    m.ranges[i] = scan.IsReturn(i) ? scan.ranges[i] : std::numeric_limits<float>::quiet_NaN();
  }
  return m;
}

std::filesystem::path ReplayFile(const AgentOptions& o) { return std::filesystem::path(o.spool_dir) / "replay.json"; }

}  // namespace

Agent::Agent(AgentOptions options, std::unique_ptr<ScanSource> source)
    : options_(std::move(options)),
      source_(std::move(source)),
      follower_(options_.follower),
      safety_(options_.safety),
      stall_(options_.stall) {
  SpoolOptions spool;
  spool.directory = options_.spool_dir;
  spool.max_bytes = static_cast<std::uint64_t>(options_.spool_max_mb * 1024 * 1024);
  spool.segment_bytes = std::min<std::uint64_t>(spool.segment_bytes, std::max<std::uint64_t>(spool.max_bytes / 8, 4096));
  spool_ = std::make_unique<Spool>(spool);

  if (options_.close_on_exit) CloseLeftoverSession();

  ServerLinkOptions link;
  link.host = options_.server_host;
  link.port = options_.server_port;
  link.other_servers = options_.other_servers;
  link.token = options_.token;
  link.binary_scans = options_.binary_scans;
  link.session_file = std::filesystem::path(options_.spool_dir) / "session.json";
  HelloMessage hello;
  hello.robot_id = options_.robot_id;
  hello.session_name = options_.session_name;
  hello.settings_json = options_.session_settings_json;
  hello.laser = source_->laser();
  link_options_ = link;
  link_ = std::make_unique<ServerLink>(link, *spool_, hello);
}

void Agent::ContinueReplay() {
  const std::string name = source_->replay_name();
  if (name.empty()) return;
  // What this replay already put in the spool is sent (or was acknowledged) in the session being
  // resumed; the replay continues after it. Without a session to resume and with nothing left to
  // send, it is a fresh run from the top.
  const auto position = LoadReplayPosition(ReplayFile(options_));
  const bool resuming = position && position->log == name && position->first_seq <= spool_->next_seq() &&
                        (LoadSessionState(link_options_.session_file) || !spool_->empty_of_unacked());
  if (!resuming) {
    SaveReplayPosition(ReplayFile(options_), {name, spool_->next_seq()});
    return;
  }
  const std::uint64_t spooled = spool_->next_seq() - position->first_seq;
  const std::uint64_t skipped = source_->Skip(spooled);
  PSLAM_LOG(kInfo) << "continuing the replay of " << name << " after the " << skipped
                   << " message(s) the previous run spooled";
  if (skipped < spooled) {
    PSLAM_LOG(kWarning) << "the log holds fewer messages (" << skipped << ") than the previous run spooled (" << spooled
                        << "): is it the same file?";
  }
}

void Agent::CloseFinishedSession() {
  const std::string session = link_->status().session_id;
  if (session.empty()) return;
  if (const auto error = CloseServerSession(link_options_, session, kCloseTimeoutSeconds)) {
    PSLAM_LOG(kWarning) << "cannot close session " << session << " (" << *error
                        << "); it stays open on the server until closed there or by a rerun";
    return;
  }
  PSLAM_LOG(kInfo) << "closed session " << session << " on the server";
  // Done: the next run is a new replay in a new session.
  ClearSessionState(link_options_.session_file);
  std::error_code ignored;
  std::filesystem::remove(ReplayFile(options_), ignored);
}

Agent::~Agent() {
  if (link_) link_->Stop();
}

void Agent::Append(const std::vector<std::uint8_t>& payload, const std::atomic<bool>& stop) {
  if (source_->can_wait()) {
    // A replay loses nothing: wait for acknowledgements to make room.
    bool reported = false;
    while (!spool_->WouldFit(payload.size()) && !stop && !link_->refusal()) {
      if (!reported) PSLAM_LOG(kInfo) << "spool full: replay paused until the server acknowledges";
      reported = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  if (spool_->Append(payload)) {
    if (spool_full_since_ >= 0) {
      PSLAM_LOG(kInfo) << "spool has room again; " << stats_.dropped_spool_full << " message(s) were lost while it was full";
      spool_full_since_ = -1.0;
    }
    link_->Notify();
    return;
  }
  ++stats_.dropped_spool_full;
  const double now = AgentClock::Now();
  if (spool_full_since_ < 0 || now - last_spool_full_report_ >= kSpoolFullReportPeriod) {
    if (spool_full_since_ < 0) spool_full_since_ = now;
    last_spool_full_report_ = now;
    const SpoolStats s = spool_->stats();
    PSLAM_LOG(kError) << "SPOOL FULL: " << s.bytes / (1024 * 1024) << " of " << s.max_bytes / (1024 * 1024) << " MB hold "
                      << s.unacked_records << " unacknowledged message(s); the server has not acknowledged for "
                      << now - link_->status().last_server_message_time << " s; NEW SCANS ARE BEING DROPPED ("
                      << stats_.dropped_spool_full << " so far). Raise --spool-max-mb or restore the link.";
  }
}

void Agent::Enqueue(const OdomMessage& odom) { Append(EncodeRecord(odom), *stop_); }
void Agent::Enqueue(const ScanMessage& scan) { Append(EncodeRecord(scan), *stop_); }

void Agent::DriveTick(double now) {
  if (!options_.drive || !source_->can_drive()) return;
  if (auto target = link_->TakeTarget()) {
    ++stats_.targets;
    if (latest_odometry_) {
      follower_.SetPath(MapPathToOdometry(target->path, target->pose, latest_odometry_->pose));
      path_active_ = true;
      if (target->turn > 0.0) {
        // The path's frame holds whatever the heading: it is followed once the turn is done.
        look_around_.Start(target->turn, latest_odometry_->pose.theta);
        PSLAM_LOG(kInfo) << "looking around: turning " << target->turn * 180.0 / std::numbers::pi
                         << " degrees in place while the server searches the map for the robot's place";
      }
      // The server re-plans every few seconds and mostly confirms the target: only a change is news.
      const bool same = logged_target_ && std::hypot((*logged_target_)[0] - target->target_x,
                                                     (*logged_target_)[1] - target->target_y) < kSameTargetMetres;
      if (target->path.empty()) {
        if (logged_target_) PSLAM_LOG(kInfo) << "no target: the robot stops (the server's events say why)";
        logged_target_.reset();
      } else if (!same) {
        PSLAM_LOG(kInfo) << "new target (" << target->target_x << ", " << target->target_y << ") with "
                         << target->path.size() << " waypoint(s)";
        logged_target_ = std::array<double, 2>{target->target_x, target->target_y};
      } else {
        PSLAM_LOG(kDebug) << "target (" << target->target_x << ", " << target->target_y << ") re-planned with "
                          << target->path.size() << " waypoint(s)";
      }
    }
  }
  VelocityCommand wanted;
  if (latest_odometry_) wanted.w = look_around_.Update(latest_odometry_->pose.theta);
  if (latest_odometry_ && !look_around_.active() && path_active_) {
    follower_.set_lookahead_distance(stall_.Lookahead(options_.follower.lookahead_distance, now));
    const FollowerOutput out = follower_.Update(latest_odometry_->pose);
    wanted = {out.command.linear, out.command.angular};
    if (out.goal_reached) {
      path_active_ = false;
      if (logged_target_) PSLAM_LOG(kInfo) << "target reached";
    }
  }
  SafetyDecision decision = safety_.Filter(wanted, now, link_->status().last_server_message_time);
  const bool may_move = decision.reason == StopReason::kNone || decision.reason == StopReason::kObstacle;
  if (may_move && latest_odometry_) {
    decision.command = stall_.Filter(decision.command, latest_odometry_->pose, now);
    if (stall_.stalls() > stats_.stalls) {
      stats_.stalls = stall_.stalls();
      PSLAM_LOG(kWarning) << "the wheels stalled: commanded forward, the robot did not move for "
                          << options_.stall.stall_s << " s; backing off " << options_.stall.back_off_s << " s";
    }
  } else {
    stall_.Reset();
  }
  if (decision.reason != stats_.stop_reason) {
    if (decision.reason != StopReason::kNone && (wanted.v != 0 || wanted.w != 0 || decision.reason == StopReason::kObstacle)) {
      PSLAM_LOG(kWarning) << "robot stopped: " << ToString(decision.reason);
    } else if (decision.reason == StopReason::kNone && stats_.stop_reason != StopReason::kNone) {
      PSLAM_LOG(kInfo) << "driving resumed";
    }
    stats_.stop_reason = decision.reason;
  }
  source_->Drive(decision.command);
  last_command_ = decision.command;
}

void Agent::LogStatus(double now) {
  const SpoolStats s = spool_->stats();
  const LinkStatus l = link_->status();
  static constexpr const char* kStates[] = {"disconnected", "connecting", "streaming", "REFUSED"};
  PSLAM_LOG(kInfo) << "status: " << stats_.scans << " scans, " << stats_.odometry << " odometry; link "
                   << kStates[static_cast<int>(l.state)] << ", acked " << l.acked_wire_seq << ", sent " << l.sent
                   << " (" << l.resent << " resent); spool " << s.unacked_records << " unacked, " << s.bytes / 1024
                   << " KiB" << (stats_.dropped_spool_full ? ", " + std::to_string(stats_.dropped_spool_full) + " DROPPED (full)" : "")
                   << (source_->StatsLine().empty() ? "" : "; " + source_->StatsLine());
  last_status_ = now;
}

int Agent::Run(const std::atomic<bool>& stop) {
  stop_ = &stop;
  PSLAM_LOG(kInfo) << "source: " << source_->description() << "; server " << options_.server_host << ":"
                   << options_.server_port << "; spool " << options_.spool_dir;
  const SpoolRecovery& r = spool_->recovery();
  if (r.records > 0) PSLAM_LOG(kInfo) << "spool: " << r.records << " record(s) kept from the previous run";
  ContinueReplay();
  link_->Start();
  last_status_ = AgentClock::Now();
  bool replay_done_reported = false;
  bool replay_acknowledged = false;
  int exit_code = kExitOk;
  while (!stop) {
    if (const auto refusal = link_->refusal()) {
      PSLAM_LOG(kError) << "giving up: " << *refusal;
      exit_code = link_->refusal_kind() == RefusalKind::kToken ? kExitRefused : kExitSessionRefused;
      break;
    }
    auto event = source_->Next(kPollSeconds);
    const double now = AgentClock::Now();
    if (event) {
      if (const auto* odom = std::get_if<OdometryReading>(&*event)) {
        ++stats_.odometry;
        latest_odometry_ = *odom;
        Enqueue(OdomMessage{odom->timestamp, odom->pose.x, odom->pose.y, odom->pose.theta,
                            odom->translational_velocity, odom->rotational_velocity});
      } else {
        const auto& scan = std::get<LaserScan>(*event);
        ++stats_.scans;
        safety_.OnScan(scan, now);
        Enqueue(ToMessage(scan));
      }
    } else if (source_->finished()) {
      if (spool_->empty_of_unacked()) {
        PSLAM_LOG(kInfo) << "replay finished and fully acknowledged";
        replay_acknowledged = true;
        break;
      }
      if (!replay_done_reported) {
        PSLAM_LOG(kInfo) << "replay finished; waiting for the server to acknowledge " << spool_->stats().unacked_records
                         << " message(s)";
        replay_done_reported = true;
      }
    }
    if (now - last_drive_tick_ >= kDrivePeriodSeconds) {
      DriveTick(now);
      last_drive_tick_ = now;
    }
    if (now - last_status_ >= options_.status_period_s) LogStatus(now);
  }
  if (source_->can_drive()) source_->Drive({});
  source_->Shutdown();
  spool_->Sync();
  if (options_.close_on_exit && exit_code == kExitOk) {
    CloseSessionOnExit();
  } else {
    link_->Stop();
    // After the link: closing the session ends the link too, which would otherwise open a new one.
    if (replay_acknowledged) CloseFinishedSession();
  }
  LogStatus(AgentClock::Now());
  return exit_code;
}

void Agent::CloseLeftoverSession() {
  const std::filesystem::path file = std::filesystem::path(options_.spool_dir) / "session.json";
  const auto state = LoadSessionState(file);
  if (!state) return;
  // This run starts afresh (a simulator starts at its start pose): continuing the session of a run
  // that was not stopped cleanly would join two unrelated trajectories.
  PSLAM_LOG(kWarning) << "session " << state->session_id << " was left open by a run that did not stop cleanly; "
                      << "closing it, this run starts a new one";
  if (!spool_->empty_of_unacked()) {
    PSLAM_LOG(kWarning) << "dropping the " << spool_->stats().unacked_records << " message(s) that run left in the spool";
  }
  spool_->DropAll();
  ServerLinkOptions link;
  link.host = options_.server_host;
  link.port = options_.server_port;
  link.other_servers = options_.other_servers;
  link.token = options_.token;
  if (const auto error = CloseServerSession(link, state->session_id, kCloseTimeoutSeconds)) {
    PSLAM_LOG(kWarning) << "could not close session " << state->session_id << " (" << *error << ")";
  }
  ClearSessionState(file);
}

void Agent::CloseSessionOnExit() {
  // Everything recorded belongs in the session: wait (bounded) for the server to acknowledge it.
  const double deadline = AgentClock::Now() + kFinalAckWaitSeconds;
  while (!spool_->empty_of_unacked() && AgentClock::Now() < deadline && !link_->refusal()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const std::string session = link_->status().session_id;
  const bool complete = spool_->empty_of_unacked();
  link_->Stop();
  if (session.empty()) return;
  if (!complete) {
    PSLAM_LOG(kWarning) << "session " << session << " left open: " << spool_->stats().unacked_records
                        << " message(s) are not acknowledged (the next run closes it)";
    return;
  }
  if (const auto error = CloseServerSession(link_options_, session, kCloseTimeoutSeconds)) {
    PSLAM_LOG(kWarning) << "could not close session " << session << " (" << *error << "); the next run closes it";
    return;
  }
  spool_->DropAll();  // delivered, and the session is over: a new session must not get them again
  ClearSessionState(std::filesystem::path(options_.spool_dir) / "session.json");
  PSLAM_LOG(kInfo) << "session " << session << " closed; the next run starts a new one";
}

}  // namespace pslam::agent
