#include "net/hub.hpp"

#include <algorithm>

namespace pslam::server {

std::shared_ptr<Hub::Channel> Hub::Find(const std::string& session_id, bool create) {
  std::lock_guard lock(mutex_);
  auto it = channels_.find(session_id);
  if (it != channels_.end()) return it->second;
  if (!create) return nullptr;
  auto channel = std::make_shared<Channel>();
  channels_[session_id] = channel;
  return channel;
}

void Hub::Publish(const std::string& session_id, const LiveFrame& frame) {
  const auto channel = Find(session_id, true);
  std::vector<std::shared_ptr<LiveViewer>> viewers;
  std::shared_ptr<const LiveDelta> delta;
  {
    std::lock_guard lock(channel->mutex);
    if (!channel->state) channel->state = std::make_unique<LiveState>(session_id, frame.resolution);
    delta = std::make_shared<const LiveDelta>(channel->state->Apply(frame));
    auto& list = channel->viewers;
    list.erase(std::remove_if(list.begin(), list.end(), [](const auto& w) { return w.expired(); }), list.end());
    for (const auto& weak : list) {
      if (auto v = weak.lock()) viewers.push_back(std::move(v));
    }
  }
  for (const auto& v : viewers) v->Deliver(delta);
}

std::optional<std::vector<LiveMessage>> Hub::Join(const std::string& session_id,
                                                  const std::shared_ptr<LiveViewer>& viewer) {
  const auto channel = Find(session_id, true);
  std::lock_guard lock(channel->mutex);
  channel->viewers.push_back(viewer);
  if (!channel->state) return std::nullopt;
  return channel->state->Snapshot();
}

void Hub::Leave(const std::string& session_id, const LiveViewer* viewer) {
  const auto channel = Find(session_id, false);
  if (!channel) return;
  std::lock_guard lock(channel->mutex);
  auto& list = channel->viewers;
  list.erase(std::remove_if(list.begin(), list.end(),
                            [&](const auto& w) {
                              const auto v = w.lock();
                              return !v || v.get() == viewer;
                            }),
             list.end());
}

void Hub::End(const std::string& session_id, const std::string& status) {
  std::shared_ptr<Channel> channel;
  {
    std::lock_guard lock(mutex_);
    auto it = channels_.find(session_id);
    if (it == channels_.end()) return;
    channel = it->second;
    channels_.erase(it);
  }
  std::vector<std::shared_ptr<LiveViewer>> viewers;
  {
    std::lock_guard lock(channel->mutex);
    for (const auto& weak : channel->viewers) {
      if (auto v = weak.lock()) viewers.push_back(std::move(v));
    }
  }
  for (const auto& v : viewers) v->SessionEnded(status);
}

Bytes Hub::FullTrajectory(const std::string& session_id) {
  const auto channel = Find(session_id, false);
  if (!channel) return TrajectoryMessage(0, {});
  std::lock_guard lock(channel->mutex);
  return channel->state ? channel->state->FullTrajectory() : TrajectoryMessage(0, {});
}

std::size_t Hub::viewers() const {
  std::vector<std::shared_ptr<Channel>> channels;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, c] : channels_) channels.push_back(c);
  }
  std::size_t n = 0;
  for (const auto& c : channels) {
    std::lock_guard lock(c->mutex);
    for (const auto& w : c->viewers) n += w.expired() ? 0 : 1;
  }
  return n;
}

}  // namespace pslam::server
