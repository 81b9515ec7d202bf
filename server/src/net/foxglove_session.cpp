#include "net/foxglove_session.hpp"

#include <chrono>
#include <limits>

namespace pslam::server {
namespace {

constexpr std::string_view kSubprotocols[] = {"foxglove.sdk.v1", "foxglove.websocket.v1"};
// A client only subscribes and unsubscribes: requests past this are refused with a status;
// messages past kMaxRead close the socket (1009).
constexpr std::size_t kMaxRequest = 64 * 1024;
constexpr std::size_t kMaxRead = 256 * 1024;
constexpr std::size_t kMaxQueuedStatuses = 32;  // more from a client that does not read are dropped
constexpr std::size_t kMaxQueuedControl = 1024;  // advertise/unadvertise a client did not read: too far behind

// Ops of the protocol that go with capabilities this server does not announce.
constexpr std::string_view kUnsupportedOps[] = {"advertise",        "unadvertise",  "getParameters",
                                                "setParameters",    "subscribeParameterUpdates",
                                                "unsubscribeParameterUpdates", "subscribeConnectionGraph",
                                                "unsubscribeConnectionGraph",  "fetchAsset"};

const std::string& ServerInstance() {  // tells a reconnecting client whether the server restarted
  static const std::string id = std::to_string(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count());
  return id;
}

std::optional<std::uint32_t> Uint32(const nlohmann::json& j) {
  if (j.is_number_unsigned() && j.get<std::uint64_t>() <= std::numeric_limits<std::uint32_t>::max()) {
    return static_cast<std::uint32_t>(j.get<std::uint64_t>());
  }
  if (j.is_number_integer() && j.get<std::int64_t>() >= 0 &&
      j.get<std::int64_t>() <= std::numeric_limits<std::uint32_t>::max()) {
    return static_cast<std::uint32_t>(j.get<std::int64_t>());
  }
  return std::nullopt;
}

std::string Shown(const nlohmann::json& j) {
  std::string s = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return s.size() > 60 ? s.substr(0, 60) + "…" : s;
}

}  // namespace

std::optional<std::string> ChooseFoxgloveSubprotocol(const http::request<http::string_body>& upgrade) {
  const auto fields = upgrade.equal_range(http::field::sec_websocket_protocol);
  for (auto field = fields.first; field != fields.second; ++field) {
    for (const auto& offered : http::token_list(field->value())) {
      for (const std::string_view ours : kSubprotocols) {
        if (beast::iequals(offered, beast::string_view(ours.data(), ours.size()))) return std::string(ours);
      }
    }
  }
  return std::nullopt;
}

FoxgloveSession::FoxgloveSession(tcp::socket&& socket, std::shared_ptr<ServerContext> context, std::string token,
                                 std::string subprotocol)
    : ws_(std::move(socket)), context_(std::move(context)), token_(std::move(token)), subprotocol_(std::move(subprotocol)) {}

FoxgloveSession::~FoxgloveSession() {
  context_->foxglove.Leave(this);
  for (const auto& [channel, id] : by_channel_) context_->foxglove.CountSubscriber(channel, -1);
}

void FoxgloveSession::Run(http::request<http::string_body> upgrade) {
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.set_option(websocket::stream_base::decorator([protocol = subprotocol_](websocket::response_type& res) {
    res.set(http::field::server, "pslam-server");
    res.set(http::field::sec_websocket_protocol, protocol);
  }));
  ws_.read_message_max(kMaxRead);
  ws_.async_accept(upgrade, beast::bind_front_handler(&FoxgloveSession::OnAccept, shared_from_this()));
}

void FoxgloveSession::OnAccept(beast::error_code ec) {
  if (ec) return Fail(ec, "foxglove accept");
  if (const auto refusal = context_->Track(shared_from_this(), SocketKind::kViewer, token_)) {
    return Close(websocket::close_code::try_again_later, *refusal);
  }
  Queue(MakeBytes(nlohmann::json{{"op", "serverInfo"},
                                 {"name", "pslam-server"},
                                 {"capabilities", nlohmann::json::array()},
                                 {"metadata", {{"subprotocol", subprotocol_}}},
                                 {"sessionId", ServerInstance()}}
                      .dump()));
  auto [channels, advertise] = context_->foxglove.Join(shared_from_this());
  joined_ = true;
  advertised_.insert(channels.begin(), channels.end());
  if (advertise) Queue(std::move(advertise));
  Read();
}

void FoxgloveSession::Advertise(std::vector<std::uint32_t> channels, Bytes message) {
  net::post(ws_.get_executor(), [self = shared_from_this(), channels = std::move(channels), message] {
    self->advertised_.insert(channels.begin(), channels.end());
    self->Queue(message);
  });
}

void FoxgloveSession::Unadvertise(std::vector<std::uint32_t> channels, Bytes message) {
  net::post(ws_.get_executor(), [self = shared_from_this(), channels = std::move(channels), message] {
    for (const std::uint32_t c : channels) {
      self->advertised_.erase(c);
      self->pending_.erase(c);
      if (const auto it = self->by_channel_.find(c); it != self->by_channel_.end()) {
        self->subscriptions_.erase(it->second);
        self->by_channel_.erase(it);
        self->context_->foxglove.CountSubscriber(c, -1);
      }
    }
    self->Queue(message);
  });
}

void FoxgloveSession::Deliver(std::shared_ptr<const std::vector<FoxgloveData>> data) {
  net::post(ws_.get_executor(), [self = shared_from_this(), data = std::move(data)] {
    for (const FoxgloveData& d : *data) {
      if (self->by_channel_.count(d.channel)) self->pending_[d.channel] = d;  // a newer one replaces it
    }
    self->Write();
  });
}

void FoxgloveSession::CloseForShutdown() {
  net::post(ws_.get_executor(), [self = shared_from_this()] {
    self->Close(websocket::close_code::going_away, "server shutting down");
  });
}

void FoxgloveSession::Read() {
  ws_.async_read(buffer_, beast::bind_front_handler(&FoxgloveSession::OnRead, shared_from_this()));
}

void FoxgloveSession::OnRead(beast::error_code ec, std::size_t bytes) {
  if (ec) {
    Fail(ec, "foxglove read");
    return Stop();
  }
  if (!ws_.got_text()) {
    Status(2, "binary messages are not accepted: this server does not offer client publishing");
  } else if (bytes > kMaxRequest) {
    Status(2, "message of " + std::to_string(bytes) + " bytes refused: requests are at most " +
                  std::to_string(kMaxRequest) + " bytes");
  } else {
    Handle(beast::buffers_to_string(buffer_.data()));
  }
  buffer_.consume(buffer_.size());
  Read();
}

void FoxgloveSession::Handle(const std::string& text) {
  const nlohmann::json request = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (request.is_discarded()) return Status(2, "malformed JSON message");
  const auto op = request.is_object() ? request.find("op") : request.end();
  if (!request.is_object() || op == request.end() || !op->is_string()) {
    return Status(2, "a message must be a JSON object with a string \"op\"");
  }
  const std::string name = op->get<std::string>();
  if (name == "subscribe") return Subscribe(request);
  if (name == "unsubscribe") return Unsubscribe(request);
  for (const std::string_view unsupported : kUnsupportedOps) {
    if (name == unsupported) return Status(2, "op \"" + name + "\" is not supported: the server did not announce it");
  }
  Status(2, "unknown op " + Shown(*op));
}

void FoxgloveSession::Subscribe(const nlohmann::json& request) {
  const auto list = request.find("subscriptions");
  if (list == request.end() || !list->is_array()) return Status(2, "subscribe needs an array \"subscriptions\"");
  for (const nlohmann::json& s : *list) {
    const auto id = s.is_object() && s.contains("id") ? Uint32(s["id"]) : std::nullopt;
    const auto channel = s.is_object() && s.contains("channelId") ? Uint32(s["channelId"]) : std::nullopt;
    if (!id || !channel) {
      Status(2, "subscription " + Shown(s) + " needs a uint32 \"id\" and \"channelId\"");
    } else if (subscriptions_.count(*id)) {
      Status(2, "subscription id " + std::to_string(*id) + " is already in use");
    } else if (!advertised_.count(*channel)) {
      Status(2, "channel " + std::to_string(*channel) + " is not advertised");
    } else if (by_channel_.count(*channel)) {
      Status(2, "channel " + std::to_string(*channel) + " is already subscribed (subscription " +
                    std::to_string(by_channel_[*channel]) + ")");
    } else {
      subscriptions_[*id] = *channel;
      by_channel_[*channel] = *id;
      context_->foxglove.CountSubscriber(*channel, +1);
      // The channel's current message, so a map shows at once; encoding it may take a while, so
      // off this thread.
      net::post(context_->workers, [self = shared_from_this(), channel = *channel] {
        auto latest = self->context_->foxglove.Latest(channel);
        if (!latest) return;
        net::post(self->ws_.get_executor(), [self, latest = std::move(*latest)] {
          if (!self->by_channel_.count(latest.channel)) return;
          const auto pending = self->pending_.find(latest.channel);
          if (pending == self->pending_.end() || pending->second.ns < latest.ns) self->pending_[latest.channel] = latest;
          self->Write();
        });
      });
    }
  }
}

void FoxgloveSession::Unsubscribe(const nlohmann::json& request) {
  const auto list = request.find("subscriptionIds");
  if (list == request.end() || !list->is_array()) return Status(2, "unsubscribe needs an array \"subscriptionIds\"");
  for (const nlohmann::json& j : *list) {
    const auto id = Uint32(j);
    const auto it = id ? subscriptions_.find(*id) : subscriptions_.end();
    if (it == subscriptions_.end()) {
      Status(2, "no subscription " + Shown(j));
      continue;
    }
    pending_.erase(it->second);
    by_channel_.erase(it->second);
    context_->foxglove.CountSubscriber(it->second, -1);
    subscriptions_.erase(it);
  }
}

void FoxgloveSession::Status(int level, const std::string& message) {
  if (statuses_queued_ >= kMaxQueuedStatuses) return;
  ++statuses_queued_;
  ordered_.push_back({MakeBytes(nlohmann::json{{"op", "status"}, {"level", level}, {"message", message}}.dump(
                          -1, ' ', false, nlohmann::json::error_handler_t::replace)),
                      true});
  Write();
}

void FoxgloveSession::Queue(Bytes message) {
  if (ordered_.size() >= kMaxQueuedControl) return Close(websocket::close_code::policy_error, "too far behind");
  ordered_.push_back({std::move(message), false});
  Write();
}

void FoxgloveSession::Write() {
  if (writing_ || close_started_ || ended_) return;
  if (!ordered_.empty()) {
    auto [message, status] = std::move(ordered_.front());
    ordered_.pop_front();
    in_flight_ = std::move(message);
    if (status) --statuses_queued_;
    writing_ = true;
    ws_.text(true);
    ws_.async_write(net::buffer(*in_flight_), beast::bind_front_handler(&FoxgloveSession::OnWrite, shared_from_this()));
    return;
  }
  if (close_) {
    close_started_ = true;
    ws_.async_close(*close_, [self = shared_from_this()](beast::error_code ec) {
      if (ec) Fail(ec, "foxglove close");
      self->Stop();
    });
    return;
  }
  if (pending_.empty()) return;
  auto next = pending_.upper_bound(last_channel_sent_);  // round robin: no channel starves the others
  if (next == pending_.end()) next = pending_.begin();
  const FoxgloveData data = std::move(next->second);
  pending_.erase(next);
  last_channel_sent_ = data.channel;
  const auto sub = by_channel_.find(data.channel);
  if (sub == by_channel_.end()) return Write();
  header_ = MessageDataHeader(sub->second, data.ns);
  in_flight_ = data.payload;
  writing_ = true;
  ws_.binary(true);
  const std::array<net::const_buffer, 2> buffers = {net::buffer(header_), net::buffer(*in_flight_)};
  ws_.async_write(buffers, beast::bind_front_handler(&FoxgloveSession::OnWrite, shared_from_this()));
}

void FoxgloveSession::OnWrite(beast::error_code ec, std::size_t) {
  writing_ = false;
  in_flight_ = nullptr;
  if (ec) {
    Fail(ec, "foxglove write");
    return Stop();
  }
  Write();
}

void FoxgloveSession::Close(websocket::close_code code, const std::string& reason) {
  if (close_ || ended_) return;
  close_ = websocket::close_reason(code, reason);
  pending_.clear();  // what is ordered (a status) still goes out; message data no longer matters
  Write();
}

void FoxgloveSession::Stop() {
  ended_ = true;
  context_->foxglove.Leave(this);
}

}  // namespace pslam::server
