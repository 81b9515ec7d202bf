#include "net/live_fanout.hpp"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cstring>
#include <iostream>
#include <optional>
#include <random>

#include "service/live_envelope.hpp"

namespace pslam::server {
namespace {

constexpr std::size_t kMaxQueued = 256;               // envelopes waiting for Redis, all sessions
constexpr std::size_t kMaxQueuedBytes = 64u << 20;    // and their bytes
constexpr auto kConnectTimeout = std::chrono::milliseconds(1000);
constexpr auto kMaxBackoff = std::chrono::milliseconds(5000);
constexpr auto kSyncInterval = std::chrono::seconds(1);  // at most one keyframe request per session per second

std::int64_t NowMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::uint64_t RandomNode() {
  std::random_device device;
  return (std::uint64_t{device()} << 32) ^ device();
}

std::size_t SizeOf(const LiveDelta& d) {
  std::size_t n = 64;
  for (const auto& [key, frame] : d.tiles) n += frame->size();
  for (const Bytes& b : {d.pose, d.scan, d.particles, d.stats, d.exploration}) n += b ? b->size() : 0;
  for (const auto& [id, message] : d.hypotheses) n += message->size();
  return n + (d.trajectory ? 48 * d.trajectory->size() : 0);
}

std::size_t SizeOf(const std::vector<LiveMessage>& snapshot) {
  std::size_t n = 64;
  for (const LiveMessage& m : snapshot) n += m.data->size();
  return n;
}

// Logs a recurring problem at most once a second, with how often it happened meanwhile.
class LimitedLog {
 public:
  void Write(const std::string& line) {
    const auto now = std::chrono::steady_clock::now();
    ++count_;
    if (now - last_ < std::chrono::seconds(1)) return;
    std::cerr << "live fan-out: " << line << " (" << count_ << " so far)\n";
    last_ = now;
  }

 private:
  std::chrono::steady_clock::time_point last_{};
  std::uint64_t count_ = 0;
};

LimitedLog& RejectLog() {
  static LimitedLog log;  // subscriber thread only
  return log;
}

LimitedLog& OverflowLog() {
  static LimitedLog log;  // under the queue's lock
  return log;
}

std::chrono::milliseconds NextBackoff(std::chrono::milliseconds b) { return std::min(b * 2, kMaxBackoff); }

}  // namespace

LiveFanout::LiveFanout(RedisAddress address, Hub& hub) : address_(std::move(address)), hub_(hub), node_(RandomNode()) {
  if (pipe2(wake_, O_NONBLOCK | O_CLOEXEC) != 0) throw std::runtime_error("live fan-out: cannot create a pipe");
  publisher_ = std::thread([this] { PublishLoop(); });
  subscriber_ = std::thread([this] { SubscribeLoop(); });
}

LiveFanout::~LiveFanout() {
  Stop();
  close(wake_[0]);
  close(wake_[1]);
}

void LiveFanout::Stop() {
  if (stopping_.exchange(true)) return;
  queue_ready_.notify_all();
  Wake();
  if (publisher_.joinable()) publisher_.join();
  if (subscriber_.joinable()) subscriber_.join();
  const LiveFanoutCounters& c = counters_;
  std::cerr << "live fan-out: published " << c.published << " messages (" << c.published_bytes << " bytes), dropped "
            << c.dropped << ", " << c.publish_failures << " Redis failures; received " << c.received << ", rejected "
            << c.rejected << ", " << c.gaps << " gaps\n";
}

void LiveFanout::Wake() {
  const char byte = 0;
  (void)!write(wake_[1], &byte, 1);
}

// ---- Publishing (engine threads queue, the publisher thread sends) ----

LiveFanout::Outgoing LiveFanout::NewItem(Outgoing::Kind kind, const std::string& session_id, std::uint64_t seq) {
  Outgoing item;
  item.kind = kind;
  item.session_id = session_id;
  item.seq = seq;
  item.published_us = NowMicros();
  return item;
}

bool LiveFanout::Offer(Outgoing item) {
  if (queue_.size() >= kMaxQueued || queued_bytes_ + item.bytes > kMaxQueuedBytes) {
    ++counters_.dropped;
    OverflowLog().Write("Redis does not keep up: dropped a message of " + item.session_id + ", a keyframe follows");
    return false;
  }
  queued_bytes_ += item.bytes;
  queue_.push_back(std::move(item));
  queue_ready_.notify_one();
  return true;
}

bool LiveFanout::OfferKeyframe(const std::string& session_id, const LiveState& state) {
  {
    // A cheap check first: a full queue would refuse the snapshot anyway.
    std::lock_guard lock(queue_mutex_);
    if (queue_.size() >= kMaxQueued) {
      ++counters_.dropped;
      OverflowLog().Write("Redis does not keep up: no room for a keyframe of " + session_id);
      sessions_[session_id].keyframe_due = true;
      return false;
    }
  }
  // Built outside the queue's lock, so other sessions' engines do not wait for it; the caller
  // holds the session's lock, so none of its ticks can pass it.
  std::vector<LiveMessage> snapshot = state.Snapshot();
  std::lock_guard lock(queue_mutex_);
  PublishedSession& session = sessions_[session_id];
  Outgoing item = NewItem(Outgoing::Kind::kKeyframe, session_id, session.seq);
  item.snapshot = std::move(snapshot);
  item.bytes = SizeOf(item.snapshot);
  session.keyframe_due = !Offer(std::move(item));
  if (!session.keyframe_due) ++session.seq;
  return !session.keyframe_due;
}

void LiveFanout::Published(const std::string& session_id, const std::shared_ptr<const LiveDelta>& delta,
                           const LiveState& state) {
  {
    std::lock_guard lock(queue_mutex_);
    PublishedSession& session = sessions_[session_id];
    if (!session.keyframe_due) {
      Outgoing item = NewItem(Outgoing::Kind::kDelta, session_id, session.seq);
      item.delta = delta;
      item.bytes = SizeOf(*delta);
      if (Offer(std::move(item))) {
        ++session.seq;
      } else {
        session.keyframe_due = true;  // receivers would miss this tick: the next message is whole
      }
      return;
    }
  }
  OfferKeyframe(session_id, state);
}

void LiveFanout::Keyframe(const std::string& session_id, const LiveState& state) { OfferKeyframe(session_id, state); }

void LiveFanout::Ended(const std::string& session_id, const std::string& status) {
  std::lock_guard lock(queue_mutex_);
  const auto it = sessions_.find(session_id);
  Outgoing item = NewItem(Outgoing::Kind::kEnd, session_id, it == sessions_.end() ? 0 : it->second.seq);
  item.status = status;
  item.bytes = 64 + status.size();
  Offer(std::move(item));
  if (it != sessions_.end()) sessions_.erase(it);
}

void LiveFanout::RequestSync(const std::string& session_id) {
  std::lock_guard lock(queue_mutex_);
  Outgoing item = NewItem(Outgoing::Kind::kSyncRequest, session_id, 0);
  item.bytes = 64;
  Offer(std::move(item));
}

bool LiveFanout::PublishOne(RedisConnection& redis, const Outgoing& item) {
  std::string channel, payload;
  switch (item.kind) {
    case Outgoing::Kind::kDelta:
      payload = EncodeDeltaEnvelope(node_, item.seq, item.published_us, *item.delta);
      break;
    case Outgoing::Kind::kKeyframe:
      payload = EncodeKeyframeEnvelope(node_, item.seq, item.published_us, item.snapshot);
      break;
    case Outgoing::Kind::kEnd:
      payload = EncodeEndEnvelope(node_, item.seq, item.published_us, item.status);
      break;
    case Outgoing::Kind::kSyncRequest:
      payload = std::to_string(node_);
      break;
  }
  if (payload.size() > kMaxLiveEnvelope) {
    std::cerr << "live fan-out: " << item.session_id << ": a message of " << payload.size() << " bytes is too large to publish\n";
    ++counters_.dropped;
    return true;  // not Redis's fault: the connection is fine
  }
  channel = (item.kind == Outgoing::Kind::kSyncRequest ? kLiveSyncPrefix : kLiveChannelPrefix) + item.session_id;
  auto* reply = static_cast<redisReply*>(
      redisCommand(redis.get(), "PUBLISH %b %b", channel.data(), channel.size(), payload.data(), payload.size()));
  if (!reply) return false;
  const bool ok = reply->type != REDIS_REPLY_ERROR;
  freeReplyObject(reply);
  if (!ok) return false;
  ++counters_.published;
  counters_.published_bytes += payload.size();
  return true;
}

void LiveFanout::PublishLoop() {
  std::unique_ptr<RedisConnection> redis;
  auto backoff = std::chrono::milliseconds(100);
  auto retry_at = std::chrono::steady_clock::now();
  LimitedLog failures;
  std::optional<std::chrono::steady_clock::time_point> drain_until;
  for (;;) {
    {
      std::unique_lock lock(queue_mutex_);
      queue_ready_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) {
        if (!drain_until) drain_until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
        if (queue_.empty() || !redis || std::chrono::steady_clock::now() > *drain_until) return;
      }
      if (!redis && std::chrono::steady_clock::now() < retry_at) {
        // Backing off: messages wait in the queue (engines drop theirs when it is full).
        queue_ready_.wait_until(lock, retry_at, [&] { return stopping_.load(); });
        continue;
      }
    }
    if (!redis) {
      auto connected = RedisConnection::Connect(address_, kConnectTimeout);
      if (!connected) {
        ++counters_.publish_failures;
        failures.Write("cannot connect to Redis at " + address_.host + ":" + std::to_string(address_.port) + ": " + connected.error());
        retry_at = std::chrono::steady_clock::now() + backoff;
        backoff = NextBackoff(backoff);
        continue;
      }
      redis = std::move(connected.value());
      if (backoff > std::chrono::milliseconds(100)) std::cerr << "live fan-out: publishing to Redis again\n";
      backoff = std::chrono::milliseconds(100);
    }
    Outgoing item;
    {
      std::lock_guard lock(queue_mutex_);
      if (queue_.empty()) continue;
      item = std::move(queue_.front());
      queue_.pop_front();
      queued_bytes_ -= item.bytes;
    }
    if (PublishOne(*redis, item)) continue;
    ++counters_.publish_failures;
    failures.Write("publishing failed: " + redis->error());
    redis.reset();
    retry_at = std::chrono::steady_clock::now() + backoff;
    backoff = NextBackoff(backoff);
    // The message is lost: receivers of its session need the whole picture again.
    ++counters_.dropped;
    std::lock_guard lock(queue_mutex_);
    if (const auto it = sessions_.find(item.session_id); it != sessions_.end()) it->second.keyframe_due = true;
  }
}

// ---- Subscribing (Hub::Join/Leave say what; the subscriber thread does it) ----

void LiveFanout::Watch(const std::string& session_id) {
  std::lock_guard lock(watch_mutex_);
  if (watched_.insert(session_id).second) Wake();
}

void LiveFanout::Unwatch(const std::string& session_id) {
  std::lock_guard lock(watch_mutex_);
  if (watched_.erase(session_id)) Wake();
}

bool LiveFanout::SyncSubscriptions(RedisConnection& redis, std::set<std::string>& subscribed) {
  std::set<std::string> wanted;
  {
    std::lock_guard lock(watch_mutex_);
    wanted = watched_;
  }
  auto command = [&](const char* verb, const std::string& id) {
    const std::string channel = kLiveChannelPrefix + id;
    const char* argv[] = {verb, channel.c_str()};
    const std::size_t lengths[] = {std::strlen(verb), channel.size()};
    redisAppendCommandArgv(redis.get(), 2, argv, lengths);
  };
  for (const auto& id : wanted) {
    if (!subscribed.count(id)) command("SUBSCRIBE", id);
  }
  for (auto it = subscribed.begin(); it != subscribed.end();) {
    if (wanted.count(*it)) {
      ++it;
      continue;
    }
    command("UNSUBSCRIBE", *it);
    incoming_.erase(*it);
    it = subscribed.erase(it);
  }
  for (const auto& id : wanted) subscribed.insert(id);
  int done = 0;
  while (!done) {  // whatever is queued on the connection, PSUBSCRIBE included
    if (redisBufferWrite(redis.get(), &done) != REDIS_OK) return false;
  }
  return true;
}

void LiveFanout::SubscribeLoop() {
  auto backoff = std::chrono::milliseconds(100);
  LimitedLog failures;
  while (!stopping_) {
    auto connected = RedisConnection::Connect(address_, kConnectTimeout);
    if (!connected) {
      failures.Write("cannot subscribe at Redis " + address_.host + ":" + std::to_string(address_.port) + ": " + connected.error());
      pollfd wake{wake_[0], POLLIN, 0};
      poll(&wake, 1, static_cast<int>(backoff.count()));
      backoff = NextBackoff(backoff);
      continue;
    }
    backoff = std::chrono::milliseconds(100);
    RedisConnection& redis = *connected.value();
    const std::string pattern = std::string(kLiveSyncPrefix) + "*";
    redisAppendCommand(redis.get(), "PSUBSCRIBE %b", pattern.data(), pattern.size());
    std::set<std::string> subscribed;
    incoming_.clear();
    bool healthy = true;
    while (healthy && !stopping_) {
      healthy = SyncSubscriptions(redis, subscribed);
      pollfd fds[2] = {{redis.get()->fd, POLLIN, 0}, {wake_[0], POLLIN, 0}};
      if (!healthy || poll(fds, 2, 500) < 0) break;
      if (fds[1].revents) {
        char drain[64];
        while (read(wake_[0], drain, sizeof drain) > 0) {
        }
      }
      if (!fds[0].revents) continue;
      if (redisBufferRead(redis.get()) != REDIS_OK) break;
      void* reply = nullptr;
      while (redisGetReplyFromReader(redis.get(), &reply) == REDIS_OK && reply) {
        HandleReply(*static_cast<redisReply*>(reply));
        freeReplyObject(reply);
        reply = nullptr;
      }
      healthy = redis.get()->err == 0;
    }
    if (!stopping_) failures.Write("lost the subscription connection: " + redis.error());
  }
}

void LiveFanout::HandleReply(const redisReply& reply) {
  if (reply.type != REDIS_REPLY_ARRAY || reply.elements < 3) return;
  auto text = [&](std::size_t i) {
    const redisReply* e = reply.element[i];
    return e->type == REDIS_REPLY_STRING ? std::string_view(e->str, e->len) : std::string_view();
  };
  const std::string_view kind = text(0);
  if (kind == "subscribe") {
    // Subscribed: now a keyframe cannot pass us by. Ask the owner for one.
    const std::string_view channel = text(1);
    if (channel.rfind(kLiveChannelPrefix, 0) != 0) return;
    const std::string id(channel.substr(std::strlen(kLiveChannelPrefix)));
    incoming_[id].last_sync = std::chrono::steady_clock::now();
    RequestSync(id);
  } else if (kind == "message") {
    const std::string_view channel = text(1);
    const redisReply* payload = reply.element[2];
    if (channel.rfind(kLiveChannelPrefix, 0) != 0 || payload->type != REDIS_REPLY_STRING) return;
    HandleLive(std::string(channel.substr(std::strlen(kLiveChannelPrefix))), payload->str, payload->len);
  } else if (kind == "pmessage" && reply.elements >= 4) {
    const std::string_view channel = text(2);
    if (channel.rfind(kLiveSyncPrefix, 0) == 0) hub_.RequestKeyframe(std::string(channel.substr(std::strlen(kLiveSyncPrefix))));
  }
}

void LiveFanout::HandleLive(const std::string& session_id, const char* data, std::size_t size) {
  ++counters_.received;
  const auto tracked = incoming_.find(session_id);
  if (tracked == incoming_.end()) return;  // unsubscribed meanwhile
  Incoming& in = tracked->second;
  auto resync = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (now - in.last_sync < kSyncInterval) return;
    in.last_sync = now;
    RequestSync(session_id);
  };
  auto envelope = DecodeLiveEnvelope(std::string_view(data, size));
  if (!envelope) {
    ++counters_.rejected;
    RejectLog().Write(session_id + ": dropped a bad message of " + std::to_string(size) + " bytes: " + envelope.error());
    return resync();
  }
  LiveEnvelope& e = envelope.value();
  if (e.node == node_) return;  // our own, from when the session ran elsewhere
  try {
    switch (e.kind) {
      case LiveEnvelope::Kind::kDelta:
        if (e.node != in.node || e.seq != in.next_seq) {
          ++counters_.gaps;  // missed messages, or a new owner whose keyframe we missed
          resync();
        }
        hub_.MirrorDelta(session_id, e.delta);
        break;
      case LiveEnvelope::Kind::kKeyframe:
        hub_.MirrorKeyframe(session_id, e.snapshot, e.tiles);
        break;
      case LiveEnvelope::Kind::kEnd:
        hub_.MirrorEnd(session_id, e.status);
        break;
    }
    in.node = e.node;
    in.next_seq = e.seq + 1;
  } catch (const std::exception& ex) {
    ++counters_.rejected;
    RejectLog().Write(session_id + ": dropped a message that does not parse: " + ex.what());
    resync();
  }
}

}  // namespace pslam::server
