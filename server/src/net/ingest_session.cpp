#include "net/ingest_session.hpp"

#include <iostream>

namespace pslam::server {
namespace {
constexpr std::size_t kReadChunk = 64 * 1024;
constexpr std::size_t kMaxQueuedErrors = 32;
constexpr auto kPausedPingPeriod = std::chrono::seconds(1);
}  // namespace

IngestSession::IngestSession(tcp::socket&& socket, std::shared_ptr<ServerContext> context, Access access,
                             std::string remote, std::string token)
    : ws_(std::move(socket)),
      context_(std::move(context)),
      access_(access),
      remote_(std::move(remote)),
      token_(std::move(token)),
      hello_deadline_(ws_.get_executor()),
      keepalive_(ws_.get_executor()) {}

IngestSession::~IngestSession() {
  if (runtime_) context_->mapping.Detach(runtime_, this);
}

void IngestSession::Run(http::request<http::string_body> upgrade) {
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.set_option(websocket::stream_base::decorator(
      [](websocket::response_type& res) { res.set(http::field::server, "pslam-server"); }));
  // Beast refuses (and closes with 1009) a frame that announces more than this by itself; smaller
  // oversize messages are caught by OnRead, which can still answer with a protocol error first.
  ws_.read_message_max(2 * context_->limits.max_message_bytes + kReadChunk);
  ws_.async_accept(upgrade, beast::bind_front_handler(&IngestSession::OnAccept, shared_from_this()));
}

void IngestSession::OnAccept(beast::error_code ec) {
  if (ec) return Fail(ec, "ingest accept");
  ++context_->agents;
  if (access_ < Access::kWrite) {
    context_->LogRefusal("WS", "/api/ingest", remote_, 401);
    Send(ErrorMessage("unauthorized", "an agent token is required"));
    CloseAfterSending(websocket::close_code::policy_error, "unauthorized");
    return;
  }
  if (const auto refusal = context_->Track(shared_from_this(), SocketKind::kAgent, token_)) {
    Send(ErrorMessage("overloaded", *refusal));
    CloseAfterSending(websocket::close_code::try_again_later, *refusal);
    return;
  }
  // A socket that never says hello would hold its slot until the idle timeout (minutes).
  hello_deadline_.expires_after(context_->limits.hello_timeout);
  hello_deadline_.async_wait(beast::bind_front_handler(&IngestSession::OnHelloDeadline, shared_from_this()));
  ReadMore();
}

void IngestSession::OnHelloDeadline(beast::error_code ec) {
  if (ec || greeted_ || close_ || ended_) return;
  if (opening_) {
    hello_late_ = true;  // decided when the hello's answer comes
    return;
  }
  CloseUngreeted("no hello within " + std::to_string(context_->limits.hello_timeout.count()) + " s");
}

void IngestSession::CloseSilent() {
  net::post(ws_.get_executor(), [self = shared_from_this()] {
    if (!self->greeted_) self->CloseUngreeted("the agent connection quota is full and this socket said no hello");
  });
}

void IngestSession::CloseUngreeted(const std::string& why) {
  std::cerr << "ingest " << remote_ << ": " << why << ", closed\n";
  // The peer may never read: do not wait long for its half of the close handshake.
  websocket::stream_base::timeout timeouts = websocket::stream_base::timeout::suggested(beast::role_type::server);
  timeouts.handshake_timeout = std::chrono::seconds(2);
  ws_.set_option(timeouts);
  Send(ErrorMessage("hello_timeout", why));
  CloseAfterSending(websocket::close_code::protocol_error, "no hello");
}

void IngestSession::ReadMore() {
  if (reading_ || paused_ || opening_ || close_ || ended_) return;
  reading_ = true;
  ws_.async_read_some(buffer_, kReadChunk, beast::bind_front_handler(&IngestSession::OnRead, shared_from_this()));
}

void IngestSession::OnRead(beast::error_code ec, std::size_t) {
  reading_ = false;
  if (ec) {
    if (ec == websocket::error::message_too_big) {
      std::cerr << "ingest " << remote_ << ": message above the hard limit, closed\n";
    } else {
      Fail(ec, "ingest read");
    }
    return OnEnded();
  }
  if (buffer_.size() > context_->limits.max_message_bytes) {
    buffer_.clear();
    Send(ErrorMessage("too_large", "messages are limited to " + std::to_string(context_->limits.max_message_bytes) + " bytes"));
    CloseAfterSending(websocket::close_code::too_big, "message too large");
    return;
  }
  if (!ws_.is_message_done()) {
    reading_ = true;
    ws_.async_read_some(buffer_, kReadChunk, beast::bind_front_handler(&IngestSession::OnRead, shared_from_this()));
    return;
  }
  HandleMessage();
  buffer_.consume(buffer_.size());
  ReadMore();
}

void IngestSession::HandleMessage() {
  const auto data = buffer_.cdata();
  IngestMessage message;
  if (ws_.got_binary()) {
    message = DecodeBinaryScan(std::span<const std::uint8_t>(static_cast<const std::uint8_t*>(data.data()), data.size()),
                               laser_ ? &*laser_ : nullptr);
  } else {
    message = DecodeTextMessage(std::string_view(static_cast<const char*>(data.data()), data.size()),
                                laser_ ? &*laser_ : nullptr, context_->mapping.options().limits);
  }
  if (auto* error = std::get_if<IngestError>(&message)) return Send(ErrorMessage(error->code, error->message));
  if (auto* hello = std::get_if<HelloMessage>(&message)) return HandleHello(std::move(*hello));
  HandleInput(std::move(std::get<InputRecord>(message)));
}

void IngestSession::HandleHello(HelloMessage hello) {
  opening_ = true;  // no reads until the session is open: inputs must not overtake it
  const std::weak_ptr<IngestSession> weak = shared_from_this();
  context_->mapping.OpenForAgent(hello, shared_from_this(), [weak](MappingService::AgentOpen opened) {
    if (const auto self = weak.lock()) {
      net::post(self->ws_.get_executor(), [self, opened = std::move(opened)]() mutable { self->OnOpened(std::move(opened)); });
    }
  });
}

void IngestSession::OnOpened(MappingService::AgentOpen opened) {
  opening_ = false;
  if (!opened.redirect.empty()) {
    Send(RedirectMessage(opened.redirect));
    return CloseAfterSending(websocket::close_code::normal, "redirect to " + opened.redirect);
  }
  if (opened.error) {
    Send(ErrorMessage(opened.error->code, opened.error->message));
    if (hello_late_) return CloseUngreeted("no valid hello within " + std::to_string(context_->limits.hello_timeout.count()) + " s");
    // A bad hello or an unknown session may be followed by a better hello; anything else ends it.
    if (opened.error->code != "bad_message" && opened.error->code != "unknown_session") {
      CloseAfterSending(websocket::close_code::try_again_later, opened.error->code);
      return;
    }
    return ReadMore();
  }
  runtime_ = opened.runtime;
  greeted_ = true;
  hello_deadline_.cancel();
  laser_ = runtime_->laser;
  ack_sent_ = ack_wanted_ = opened.last_acked_seq;
  Send(WelcomeMessage(runtime_->id, opened.last_acked_seq));
  ReadMore();
}

void IngestSession::HandleInput(InputRecord input) {
  // No session: none opened yet, or the service let go of it (a storage error) while this input
  // was already being read. Either way nothing may be admitted.
  if (!runtime_) return Send(ErrorMessage("bad_message", "no open session: send hello first"));
  const std::int64_t seq = input.seq;
  const auto result = context_->mapping.Admit(runtime_, this, std::move(input));
  switch (result.admission) {
    case MappingService::Admission::kAccepted:
      break;
    case MappingService::Admission::kDuplicate:
      // Already in: acknowledged again once it is stored (now, if it already is).
      if (result.committed_seq >= seq) {
        ack_wanted_ = std::max(ack_wanted_, result.committed_seq);
        ack_sent_ = std::min(ack_sent_, seq - 1);  // force a fresh ack for the resend
        Write();
      }
      return;
    case MappingService::Admission::kOutOfOrder:
      Send(ErrorMessage("bad_message", "seq " + std::to_string(seq) + " is out of order: expected " +
                                           std::to_string(result.expected_seq) + " (resend from there)"));
      return;
    case MappingService::Admission::kImplausible:
      Send(ErrorMessage("bad_message", result.problem));  // not stored: the agent may send a corrected one
      return;
    case MappingService::Admission::kClosed:
      Send(ErrorMessage("closed", "the session is closed"));
      CloseAfterSending(websocket::close_code::normal, "session closed");
      return;
    case MappingService::Admission::kNotOwner:
      Send(ErrorMessage("replaced", "a newer connection of the agent took the session"));
      CloseAfterSending(websocket::close_code::normal, "replaced");
      return;
  }
  if (!paused_ && context_->mapping.PauseIfOverloaded(runtime_)) {
    paused_ = true;
    // While paused no read is pending, and nothing else holds the session once the last ack is
    // written: keep it alive until Resume() (the service holds only a weak pointer).
    paused_self_ = shared_from_this();
    Send(ErrorMessage("overloaded", "the filter is behind; wait for acks before sending more"));
    KeepAliveWhilePaused();
  }
}

void IngestSession::KeepAliveWhilePaused() {
  keepalive_.expires_after(kPausedPingPeriod);
  keepalive_.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (ec || !self->paused_ || self->ended_ || self->close_) return;
    self->ping_wanted_ = true;
    self->Write();
    self->KeepAliveWhilePaused();
  });
}

void IngestSession::SendAck(std::int64_t seq) {
  net::post(ws_.get_executor(), [self = shared_from_this(), seq] {
    self->ack_wanted_ = std::max(self->ack_wanted_, seq);
    self->Write();
  });
}

void IngestSession::SendTarget(const ExplorationTarget& target) {
  net::post(ws_.get_executor(), [self = shared_from_this(), message = TargetMessage(target)]() mutable {
    self->pending_target_ = std::move(message);  // only the newest target matters
    self->Write();
  });
}

void IngestSession::Resume() {
  net::post(ws_.get_executor(), [self = shared_from_this()] {
    self->paused_ = false;
    self->paused_self_.reset();
    self->keepalive_.cancel();
    self->ReadMore();
  });
}

void IngestSession::Disconnect(const std::string& code, const std::string& reason) {
  net::post(ws_.get_executor(), [self = shared_from_this(), code, reason] {
    self->runtime_.reset();  // the service has let go of us already
    self->Send(ErrorMessage(code, reason));
    const bool internal = code == "storage_error" || code == "engine_failed";
    self->CloseAfterSending(internal ? websocket::close_code::internal_error : websocket::close_code::normal, code);
  });
}

void IngestSession::CloseForShutdown() {
  net::post(ws_.get_executor(), [self = shared_from_this()] {
    self->CloseAfterSending(websocket::close_code::going_away, "server shutting down");
  });
}

void IngestSession::Send(std::string message) {
  if (close_) return;
  if (outbox_.size() >= kMaxQueuedErrors) return;  // an agent that ignores errors does not grow our memory
  outbox_.push_back(std::move(message));
  Write();
}

void IngestSession::CloseAfterSending(websocket::close_code code, const std::string& reason) {
  if (close_) return;
  close_ = websocket::close_reason(code, reason);
  Write();
}

void IngestSession::Write() {
  if (writing_ || close_started_ || ended_) return;
  if (!outbox_.empty()) {
    in_flight_ = std::move(outbox_.front());
    outbox_.pop_front();
  } else if (ack_wanted_ > ack_sent_) {
    in_flight_ = AckMessage(ack_wanted_);
    ack_sent_ = ack_wanted_;
  } else if (pending_target_) {
    in_flight_ = std::move(*pending_target_);
    pending_target_.reset();
  } else if (ping_wanted_ && !close_) {
    ping_wanted_ = false;
    writing_ = true;
    ws_.async_ping({}, [self = shared_from_this()](beast::error_code ec) { self->OnWrite(ec, 0); });
    return;
  } else if (close_) {
    close_started_ = true;
    ws_.async_close(*close_, [self = shared_from_this()](beast::error_code ec) {
      if (ec) Fail(ec, "ingest close");
      self->OnEnded();
    });
    return;
  } else {
    return;
  }
  writing_ = true;
  ws_.text(true);
  ws_.async_write(net::buffer(in_flight_), beast::bind_front_handler(&IngestSession::OnWrite, shared_from_this()));
}

void IngestSession::OnWrite(beast::error_code ec, std::size_t) {
  writing_ = false;
  if (ec) {
    Fail(ec, "ingest write");
    return OnEnded();
  }
  Write();
}

void IngestSession::OnEnded() {
  if (ended_) return;
  ended_ = true;
  paused_self_.reset();
  hello_deadline_.cancel();
  keepalive_.cancel();
  --context_->agents;
  if (runtime_) {
    context_->mapping.Detach(runtime_, this);
    runtime_.reset();
  }
}

}  // namespace pslam::server
