#include "net/foxglove_hub.hpp"

#include <algorithm>

namespace pslam::server {
namespace {

constexpr auto kTopics = static_cast<std::uint32_t>(kFoxgloveTopics.size());

std::uint64_t WallNanoseconds() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count());
}

std::vector<std::uint32_t> ChannelsOf(std::uint32_t first) {
  std::vector<std::uint32_t> ids;
  for (std::uint32_t i = 0; i < kTopics; ++i) ids.push_back(first + i);
  return ids;
}

void AddChannels(nlohmann::json& list, const std::string& session_id, std::uint32_t first) {
  for (std::uint32_t i = 0; i < kTopics; ++i) list.push_back(ChannelJson(first + i, session_id, kFoxgloveTopics[i]));
}

Bytes AdvertiseMessage(nlohmann::json channels) {
  return MakeBytes(nlohmann::json{{"op", "advertise"}, {"channels", std::move(channels)}}.dump());
}

}  // namespace

std::shared_ptr<FoxgloveHub::Session> FoxgloveHub::FindOrAdvertise(const std::string& session_id) {
  std::shared_ptr<Session> session;
  std::vector<std::shared_ptr<FoxgloveViewer>> viewers;
  {
    std::lock_guard lock(mutex_);
    if (auto it = sessions_.find(session_id); it != sessions_.end()) return it->second;
    session = std::make_shared<Session>(session_id, timers_);
    session->first_channel = next_channel_;
    next_channel_ += kTopics;
    sessions_[session_id] = session;
    by_channel_[session->first_channel] = session;
    for (const auto& weak : viewers_) {
      if (auto v = weak.lock()) viewers.push_back(std::move(v));
    }
  }
  if (!viewers.empty()) {
    nlohmann::json channels = nlohmann::json::array();
    AddChannels(channels, session_id, session->first_channel);
    const Bytes message = AdvertiseMessage(std::move(channels));
    for (const auto& v : viewers) v->Advertise(ChannelsOf(session->first_channel), message);
  }
  return session;
}

std::vector<std::shared_ptr<FoxgloveViewer>> FoxgloveHub::Viewers() {
  std::vector<std::shared_ptr<FoxgloveViewer>> out;
  std::lock_guard lock(mutex_);
  viewers_.erase(std::remove_if(viewers_.begin(), viewers_.end(), [](const auto& w) { return w.expired(); }),
                 viewers_.end());
  for (const auto& weak : viewers_) {
    if (auto v = weak.lock()) out.push_back(std::move(v));
  }
  return out;
}

FoxgloveState::Listening FoxgloveHub::ListeningTo(const Session& session) {
  FoxgloveState::Listening listening{};
  std::lock_guard lock(mutex_);
  for (std::uint32_t i = 0; i < kTopics; ++i) {
    const auto it = subscribers_.find(session.first_channel + i);
    listening[i] = it != subscribers_.end() && it->second > 0;
  }
  return listening;
}

void FoxgloveHub::CountSubscriber(std::uint32_t channel, int delta) {
  std::lock_guard lock(mutex_);
  if ((subscribers_[channel] += delta) <= 0) subscribers_.erase(channel);
}

void FoxgloveHub::Publish(const std::string& session_id, const LiveFrame& frame) {
  const auto session = FindOrAdvertise(session_id);
  const auto listening = ListeningTo(*session);
  std::vector<FoxgloveMessage> messages;
  {
    std::lock_guard lock(session->mutex);
    if (session->ended) return;
    messages = session->state.Apply(frame, WallNanoseconds(), FoxgloveState::Clock::now(), listening);
    ArmFlush(session);
  }
  Send(*session, messages);
}

void FoxgloveHub::Send(const Session& session, const std::vector<FoxgloveMessage>& messages) {
  if (messages.empty()) return;
  auto data = std::make_shared<std::vector<FoxgloveData>>();
  for (const FoxgloveMessage& m : messages) {
    data->push_back({session.first_channel + static_cast<std::uint32_t>(m.topic), m.ns, m.payload});
  }
  for (const auto& v : Viewers()) v->Deliver(data);
}

void FoxgloveHub::ArmFlush(const std::shared_ptr<Session>& session) {
  const auto due = session->state.NextDue();
  if (!due || session->timer_armed) return;
  session->timer_armed = true;
  session->timer.expires_at(*due);
  session->timer.async_wait([this, session](beast::error_code ec) {
    if (!ec) net::post(work_, [this, session] { OnFlush(session); });
  });
}

void FoxgloveHub::OnFlush(const std::shared_ptr<Session>& session) {
  const auto listening = ListeningTo(*session);
  std::vector<FoxgloveMessage> messages;
  {
    std::lock_guard lock(session->mutex);
    session->timer_armed = false;
    if (session->ended) return;
    messages = session->state.Flush(FoxgloveState::Clock::now(), listening);
    ArmFlush(session);
  }
  Send(*session, messages);
}

void FoxgloveHub::End(const std::string& session_id) {
  std::shared_ptr<Session> session;
  std::vector<std::shared_ptr<FoxgloveViewer>> viewers;
  {
    std::lock_guard lock(mutex_);
    const auto it = sessions_.find(session_id);
    if (it == sessions_.end()) return;
    session = it->second;
    sessions_.erase(it);
    by_channel_.erase(session->first_channel);
    for (const auto& weak : viewers_) {
      if (auto v = weak.lock()) viewers.push_back(std::move(v));
    }
  }
  {
    std::lock_guard lock(session->mutex);
    session->ended = true;
    session->timer.cancel();
  }
  const auto ids = ChannelsOf(session->first_channel);
  const Bytes message = MakeBytes(nlohmann::json{{"op", "unadvertise"}, {"channelIds", ids}}.dump());
  for (const auto& v : viewers) v->Unadvertise(ids, message);
}

std::pair<std::vector<std::uint32_t>, Bytes> FoxgloveHub::Join(const std::shared_ptr<FoxgloveViewer>& viewer) {
  std::lock_guard lock(mutex_);
  viewers_.push_back(viewer);
  std::vector<std::uint32_t> ids;
  nlohmann::json channels = nlohmann::json::array();
  for (const auto& [id, session] : sessions_) {
    AddChannels(channels, id, session->first_channel);
    for (const std::uint32_t c : ChannelsOf(session->first_channel)) ids.push_back(c);
  }
  if (ids.empty()) return {};
  return {std::move(ids), AdvertiseMessage(std::move(channels))};
}

void FoxgloveHub::Leave(const FoxgloveViewer* viewer) {
  std::lock_guard lock(mutex_);
  viewers_.erase(std::remove_if(viewers_.begin(), viewers_.end(),
                                [&](const auto& w) {
                                  const auto v = w.lock();
                                  return !v || v.get() == viewer;
                                }),
                 viewers_.end());
}

std::optional<FoxgloveData> FoxgloveHub::Latest(std::uint32_t channel) {
  std::shared_ptr<Session> session;
  {
    std::lock_guard lock(mutex_);
    auto it = by_channel_.upper_bound(channel);
    if (it == by_channel_.begin()) return std::nullopt;
    --it;
    if (channel - it->first >= kTopics) return std::nullopt;
    session = it->second;
  }
  std::lock_guard lock(session->mutex);
  const auto message = session->state.Latest(kFoxgloveTopics[channel - session->first_channel]);
  if (!message) return std::nullopt;
  return FoxgloveData{channel, message->ns, message->payload};
}

}  // namespace pslam::server
