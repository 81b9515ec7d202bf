#include "net/live_session.hpp"

#include "service/api_error.hpp"
#include "service/ingest_codec.hpp"

namespace pslam::server {
namespace {
// Past this many pending trajectory poses, send one full trajectory instead of the increments.
constexpr std::size_t kMaxPendingTrajectory = 20000;
constexpr std::size_t kMaxViewerMessage = 4096;  // viewers send nothing we act on
}  // namespace

LiveSession::LiveSession(tcp::socket&& socket, std::shared_ptr<ServerContext> context, std::string session_id,
                         std::string token)
    : ws_(std::move(socket)), context_(std::move(context)), session_id_(std::move(session_id)), token_(std::move(token)) {}

LiveSession::~LiveSession() { context_->hub.Leave(session_id_, this); }

void LiveSession::Run(http::request<http::string_body> upgrade) {
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.read_message_max(kMaxViewerMessage);
  ws_.async_accept(upgrade, beast::bind_front_handler(&LiveSession::OnAccept, shared_from_this()));
}

void LiveSession::OnAccept(beast::error_code ec) {
  if (ec) return Fail(ec, "live accept");
  if (const auto refusal = context_->Track(shared_from_this(), SocketKind::kViewer, token_)) {
    return Close(websocket::close_code::try_again_later, *refusal);
  }
  Subscribe();
  Read();
}

void LiveSession::Subscribe() {
  if (auto snapshot = context_->hub.Join(session_id_, shared_from_this())) {
    subscribed_ = true;
    return Enqueue(std::move(*snapshot));
  }
  // Not running (or nothing published yet): a snapshot of what storage holds, read off this thread.
  net::post(context_->workers, [self = shared_from_this()] {
    std::vector<LiveMessage> messages;
    bool found = true;
    try {
      messages = self->context_->mapping.StoredLiveSnapshot(self->session_id_);
    } catch (const ApiError& e) {
      found = false;
      messages.push_back({MakeBytes(ErrorMessage("unknown_session", e.what())), false});
    } catch (const std::exception& e) {
      found = false;
      messages.push_back({MakeBytes(ErrorMessage("internal", "cannot read the session")), false});
    }
    net::post(self->ws_.get_executor(), [self, found, messages = std::move(messages)]() mutable {
      // Deltas that arrived meanwhile are newer than the stored state; keep them after the snapshot.
      std::deque<LiveMessage> later = std::move(self->ordered_);
      self->ordered_.clear();
      self->Enqueue(std::move(messages));
      for (auto& m : later) self->ordered_.push_back(std::move(m));
      self->subscribed_ = true;
      if (!found) self->Close(websocket::close_code::policy_error, "unknown session");
      self->Write();
    });
  });
}

void LiveSession::Enqueue(std::vector<LiveMessage> messages) {
  for (auto& m : messages) ordered_.push_back(std::move(m));
  Write();
}

void LiveSession::Deliver(std::shared_ptr<const LiveDelta> delta) {
  net::post(ws_.get_executor(), [self = shared_from_this(), delta = std::move(delta)] {
    self->Merge(*delta);
    self->Write();
  });
}

void LiveSession::Merge(const LiveDelta& d) {
  for (const auto& [key, frame] : d.tiles) tiles_[key] = frame;
  if (d.pose) pose_ = d.pose;
  if (d.scan) scan_ = d.scan;
  if (d.stats) stats_ = d.stats;
  if (d.exploration) exploration_ = d.exploration;
  if (d.particles) particles_ = d.particles;
  for (const auto& [id, message] : d.hypotheses) hypotheses_[id] = message;
  if (d.trajectory && !trajectory_resync_) {
    if (trajectory_.empty()) trajectory_first_ = d.trajectory_first_index;
    const auto expected = trajectory_first_ + static_cast<std::int64_t>(trajectory_.size());
    if (d.trajectory_first_index != expected || trajectory_.size() + d.trajectory->size() > kMaxPendingTrajectory) {
      trajectory_resync_ = true;  // not contiguous (engine restarted) or too much: send it whole
      trajectory_.clear();
    } else {
      trajectory_.insert(trajectory_.end(), d.trajectory->begin(), d.trajectory->end());
    }
  }
}

void LiveSession::SessionEnded(const std::string& status) {
  net::post(ws_.get_executor(), [self = shared_from_this(), status] {
    self->ordered_.push_back({SessionStatusMessage(self->session_id_, status), false});
    self->Write();
  });
}

void LiveSession::CloseForShutdown() {
  net::post(ws_.get_executor(), [self = shared_from_this()] {
    self->Close(websocket::close_code::going_away, "server shutting down");
  });
}

void LiveSession::Read() {
  ws_.async_read(buffer_, beast::bind_front_handler(&LiveSession::OnRead, shared_from_this()));
}

void LiveSession::OnRead(beast::error_code ec, std::size_t) {
  if (ec) {
    Fail(ec, "live read");
    ended_ = true;
    return context_->hub.Leave(session_id_, this);
  }
  buffer_.consume(buffer_.size());  // nothing a viewer says changes what it gets
  Read();
}

void LiveSession::Write() {
  if (writing_ || close_started_ || ended_ || !subscribed_) return;
  LiveMessage next;
  if (!ordered_.empty()) {
    next = std::move(ordered_.front());
    ordered_.pop_front();
  } else if (close_) {
    close_started_ = true;
    ws_.async_close(*close_, [self = shared_from_this()](beast::error_code ec) {
      if (ec) Fail(ec, "live close");
      self->ended_ = true;
      self->context_->hub.Leave(self->session_id_, self.get());
    });
    return;
  } else if (pose_) {
    next = {std::exchange(pose_, nullptr), false};
  } else if (scan_) {
    next = {std::exchange(scan_, nullptr), true};
  } else if (stats_) {
    next = {std::exchange(stats_, nullptr), false};
  } else if (exploration_) {
    next = {std::exchange(exploration_, nullptr), false};
  } else if (trajectory_resync_) {
    trajectory_resync_ = false;
    next = {context_->hub.FullTrajectory(session_id_), false};
  } else if (!trajectory_.empty()) {
    next = {TrajectoryMessage(trajectory_first_, trajectory_), false};
    trajectory_.clear();
  } else if (!hypotheses_.empty()) {
    next = {hypotheses_.begin()->second, false};
    hypotheses_.erase(hypotheses_.begin());
  } else if (particles_) {
    next = {std::exchange(particles_, nullptr), true};
  } else if (!tiles_.empty()) {
    next = {tiles_.begin()->second, true};
    tiles_.erase(tiles_.begin());
  } else {
    return;
  }
  in_flight_ = std::move(next);
  writing_ = true;
  ws_.binary(in_flight_.binary);
  ws_.async_write(net::buffer(*in_flight_.data), beast::bind_front_handler(&LiveSession::OnWrite, shared_from_this()));
}

void LiveSession::OnWrite(beast::error_code ec, std::size_t) {
  writing_ = false;
  in_flight_ = {};
  if (ec) {
    Fail(ec, "live write");
    ended_ = true;
    return context_->hub.Leave(session_id_, this);
  }
  Write();
}

void LiveSession::Close(websocket::close_code code, const std::string& reason) {
  if (close_ || ended_) return;
  close_ = websocket::close_reason(code, reason);
  // What is ordered (an error, a status) still goes out; state updates no longer matter.
  pose_ = scan_ = stats_ = exploration_ = particles_ = nullptr;
  trajectory_.clear();
  trajectory_resync_ = false;
  hypotheses_.clear();
  tiles_.clear();
  subscribed_ = true;
  Write();
}

}  // namespace pslam::server
