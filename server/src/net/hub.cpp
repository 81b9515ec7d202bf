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

std::vector<std::shared_ptr<LiveViewer>> Hub::LiveViewers(Channel& channel) {
  auto& list = channel.viewers;
  list.erase(std::remove_if(list.begin(), list.end(), [](const auto& w) { return w.expired(); }), list.end());
  std::vector<std::shared_ptr<LiveViewer>> viewers;
  for (const auto& weak : list) {
    if (auto v = weak.lock()) viewers.push_back(std::move(v));
  }
  return viewers;
}

void Hub::Publish(const std::string& session_id, const LiveFrame& frame) {
  const auto channel = Find(session_id, true);
  std::vector<std::shared_ptr<LiveViewer>> viewers;
  std::shared_ptr<const LiveDelta> delta;
  {
    std::lock_guard lock(channel->mutex);
    if (!channel->local) {
      // The session runs here now: a mirror of it (another node ran it) gives way to the engine.
      channel->local = true;
      channel->state.reset();
      if (relay_) relay_->Unwatch(session_id);
    }
    if (!channel->state) channel->state = std::make_unique<LiveState>(session_id, frame.resolution);
    delta = std::make_shared<const LiveDelta>(channel->state->Apply(frame));
    if (relay_) relay_->Published(session_id, delta, *channel->state);
    viewers = LiveViewers(*channel);
  }
  for (const auto& v : viewers) v->Deliver(delta);
}

std::optional<std::vector<LiveMessage>> Hub::Join(const std::string& session_id,
                                                  const std::shared_ptr<LiveViewer>& viewer) {
  for (;;) {
    const auto channel = Find(session_id, true);
    std::lock_guard lock(channel->mutex);
    if (channel->removed) continue;  // the last viewer of a mirror just left; a new channel is made
    channel->viewers.push_back(viewer);
    if (!channel->local && relay_) relay_->Watch(session_id);
    if (!channel->state) return std::nullopt;
    return channel->state->Snapshot();
  }
}

void Hub::Leave(const std::string& session_id, const LiveViewer* viewer) {
  const auto channel = Find(session_id, false);
  if (!channel) return;
  {
    std::lock_guard lock(channel->mutex);
    auto& list = channel->viewers;
    list.erase(std::remove_if(list.begin(), list.end(),
                              [&](const auto& w) {
                                const auto v = w.lock();
                                return !v || v.get() == viewer;
                              }),
               list.end());
    if (channel->local || !list.empty()) return;
  }
  // Nobody watches a session that does not run here: drop its channel (and mirror).
  std::lock_guard map_lock(mutex_);
  std::lock_guard lock(channel->mutex);
  if (channel->local || channel->removed || !channel->viewers.empty()) return;
  channel->removed = true;
  const auto it = channels_.find(session_id);
  if (it != channels_.end() && it->second == channel) channels_.erase(it);
  if (relay_) relay_->Unwatch(session_id);
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
    channel->removed = true;
    if (relay_) {
      if (channel->local) relay_->Ended(session_id, status);
      else relay_->Unwatch(session_id);
    }
    viewers = LiveViewers(*channel);
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

void Hub::MirrorDelta(const std::string& session_id, const LiveDelta& delta) {
  const auto channel = Find(session_id, false);
  if (!channel) return;
  std::vector<std::shared_ptr<LiveViewer>> viewers;
  {
    std::lock_guard lock(channel->mutex);
    if (channel->local || channel->removed) return;
    // Without a keyframe yet there is no picture to keep, but the viewers (who got what storage
    // holds) still take the tick, once it proved sound.
    if (channel->state) {
      channel->state->Absorb(delta);
    } else {
      LiveState(session_id, 0.05).Absorb(delta);
    }
    viewers = LiveViewers(*channel);
  }
  const auto shared = std::make_shared<const LiveDelta>(delta);
  for (const auto& v : viewers) v->Deliver(shared);
}

void Hub::MirrorKeyframe(const std::string& session_id, const std::string& snapshot, const std::vector<Bytes>& tiles) {
  const auto channel = Find(session_id, false);
  if (!channel) return;
  std::vector<std::shared_ptr<LiveViewer>> viewers;
  std::shared_ptr<const LiveDelta> delta;
  {
    std::lock_guard lock(channel->mutex);
    if (channel->local || channel->removed) return;
    if (channel->state) {
      delta = std::make_shared<const LiveDelta>(channel->state->Replace(snapshot, tiles));
    } else {
      auto state = std::make_unique<LiveState>(session_id, 0.05);
      delta = std::make_shared<const LiveDelta>(state->Replace(snapshot, tiles));
      channel->state = std::move(state);
    }
    viewers = LiveViewers(*channel);
  }
  for (const auto& v : viewers) v->Deliver(delta);
}

void Hub::MirrorEnd(const std::string& session_id, const std::string& status) {
  const auto channel = Find(session_id, false);
  if (!channel) return;
  std::vector<std::shared_ptr<LiveViewer>> viewers;
  {
    std::lock_guard lock(channel->mutex);
    if (channel->local || channel->removed) return;
    channel->state.reset();
    viewers = LiveViewers(*channel);
  }
  for (const auto& v : viewers) v->SessionEnded(status);
}

void Hub::RequestKeyframe(const std::string& session_id) {
  const auto channel = Find(session_id, false);
  if (!channel || !relay_) return;
  std::lock_guard lock(channel->mutex);
  if (channel->local && channel->state && !channel->removed) relay_->Keyframe(session_id, *channel->state);
}

}  // namespace pslam::server
