#pragma once
// Live fan-out through Redis (docs/fleet.md). A node publishes each tick of the sessions it runs,
// as the encoded messages its own viewers get, to the channel pslam:live:<id>; a node whose
// viewers watch a session running elsewhere subscribes to that channel, asks the owner for a
// keyframe on pslam:live-sync:<id>, and feeds the hub's mirror of the session.
//
// Two threads, each with its own hiredis connection. The publisher drains a bounded queue that
// engines only append to: when it is full the tick is dropped and the session's next message is a
// keyframe, so an engine never waits for Redis, and Redis being down costs counted, logged drops.
// The subscriber holds one connection in subscribe mode for the whole node. Both reconnect with
// back-off; malformed or oversized payloads are dropped with a log line.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "net/hub.hpp"
#include "net/redis_connection.hpp"

namespace pslam::server {

inline constexpr const char* kLiveChannelPrefix = "pslam:live:";
inline constexpr const char* kLiveSyncPrefix = "pslam:live-sync:";

struct LiveFanoutCounters {
  std::atomic<std::uint64_t> published{0}, published_bytes{0}, dropped{0}, publish_failures{0};
  std::atomic<std::uint64_t> received{0}, rejected{0}, gaps{0};
};

class LiveFanout : public LiveRelay {
 public:
  LiveFanout(RedisAddress address, Hub& hub);
  ~LiveFanout() override;
  LiveFanout(const LiveFanout&) = delete;
  LiveFanout& operator=(const LiveFanout&) = delete;

  // Publishes what is queued (for up to a second), stops both threads and logs the counters.
  void Stop();
  const LiveFanoutCounters& counters() const { return counters_; }

  void Published(const std::string& session_id, const std::shared_ptr<const LiveDelta>& delta,
                 const LiveState& state) override;
  void Keyframe(const std::string& session_id, const LiveState& state) override;
  void Ended(const std::string& session_id, const std::string& status) override;
  void Watch(const std::string& session_id) override;
  void Unwatch(const std::string& session_id) override;

 private:
  struct Outgoing {
    enum class Kind { kDelta, kKeyframe, kEnd, kSyncRequest } kind = Kind::kDelta;
    std::string session_id;
    std::uint64_t seq = 0;
    std::int64_t published_us = 0;
    std::shared_ptr<const LiveDelta> delta;
    std::vector<LiveMessage> snapshot;
    std::string status;
    std::size_t bytes = 0;
  };
  struct PublishedSession {
    std::uint64_t seq = 0;
    bool keyframe_due = true;  // a node's first message for a session is a keyframe
  };
  struct Incoming {  // per watched session, on the subscriber thread
    std::uint64_t node = 0, next_seq = 0;
    std::chrono::steady_clock::time_point last_sync{};
  };

  static Outgoing NewItem(Outgoing::Kind kind, const std::string& session_id, std::uint64_t seq);
  // Queues 'item' if the queue has room; the caller holds queue_mutex_.
  bool Offer(Outgoing item);
  // Queues the session's whole picture; false (and one due) if the queue is full.
  bool OfferKeyframe(const std::string& session_id, const LiveState& state);
  void RequestSync(const std::string& session_id);
  void PublishLoop();
  bool PublishOne(RedisConnection& redis, const Outgoing& item);
  void SubscribeLoop();
  bool SyncSubscriptions(RedisConnection& redis, std::set<std::string>& subscribed);
  void HandleReply(const redisReply& reply);
  void HandleLive(const std::string& session_id, const char* data, std::size_t size);
  void Wake();

  const RedisAddress address_;
  Hub& hub_;
  const std::uint64_t node_;  // random, so a node can tell its own messages and a new owner's
  LiveFanoutCounters counters_;
  std::atomic<bool> stopping_{false};

  std::mutex queue_mutex_;
  std::condition_variable queue_ready_;
  std::deque<Outgoing> queue_;
  std::size_t queued_bytes_ = 0;
  std::map<std::string, PublishedSession> sessions_;

  std::mutex watch_mutex_;
  std::set<std::string> watched_;
  int wake_[2] = {-1, -1};  // a pipe that interrupts the subscriber's poll
  std::map<std::string, Incoming> incoming_;  // subscriber thread only

  std::thread publisher_, subscriber_;
};

}  // namespace pslam::server
