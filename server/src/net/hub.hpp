#pragma once
// The live-view hub (Beast chat-multi's shared_state, per session): holds each running session's
// picture (LiveState) and its viewers. A frame is encoded once for all viewers, under the
// session's lock; delivery happens outside it and only posts to each viewer's strand, so a slow
// viewer never holds up the engine or the other viewers.
//
// With a relay (net/live_fanout.hpp), the hub also hands every local tick to other nodes, and
// keeps a mirror of each session another node runs while viewers here watch it: the mirror is a
// LiveState fed from the owner's messages, and its viewers are served exactly as local ones.
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "engine/engine_output.hpp"
#include "service/live_codec.hpp"

namespace pslam::server {

class LiveViewer {
 public:
  virtual ~LiveViewer() = default;
  // Called on the publishing thread; implementations post and return.
  virtual void Deliver(std::shared_ptr<const LiveDelta> delta) = 0;
  virtual void SessionEnded(const std::string& status) = 0;
};

// What the hub tells the fleet, and asks of it. Every call is made under the session's lock, so the
// relay sees ticks in order; implementations only queue and return.
class LiveRelay {
 public:
  virtual ~LiveRelay() = default;
  // A local tick, right after 'state' applied it.
  virtual void Published(const std::string& session_id, const std::shared_ptr<const LiveDelta>& delta,
                         const LiveState& state) = 0;
  // The whole picture, asked for by another node.
  virtual void Keyframe(const std::string& session_id, const LiveState& state) = 0;
  virtual void Ended(const std::string& session_id, const std::string& status) = 0;
  // Viewers here came for a session that does not run here / the last of them left (or it now runs here).
  virtual void Watch(const std::string& session_id) = 0;
  virtual void Unwatch(const std::string& session_id) = 0;
};

class Hub {
 public:
  // Before serving; the relay outlives the hub's use of it.
  void SetRelay(LiveRelay* relay) { relay_ = relay; }
  void Publish(const std::string& session_id, const LiveFrame& frame);
  // Registers 'viewer'. Returns the session's snapshot if it has live state (a running session),
  // atomically with the registration, so the viewer gets every later delta and no earlier one.
  std::optional<std::vector<LiveMessage>> Join(const std::string& session_id, const std::shared_ptr<LiveViewer>& viewer);
  void Leave(const std::string& session_id, const LiveViewer* viewer);
  // The session stopped running: viewers are told, its state is dropped.
  void End(const std::string& session_id, const std::string& status);
  // The whole trajectory of a running session (for a viewer whose increments overflowed).
  Bytes FullTrajectory(const std::string& session_id);
  std::size_t viewers() const;

  // From another node, for a session watched here (ignored if it runs here or nobody watches).
  // A keyframe replaces the mirror and sends viewers what changed; the end keeps the viewers
  // (another node may take the session over). They throw on malformed JSON, changing nothing.
  void MirrorDelta(const std::string& session_id, const LiveDelta& delta);
  void MirrorKeyframe(const std::string& session_id, const std::string& snapshot, const std::vector<Bytes>& tiles);
  void MirrorEnd(const std::string& session_id, const std::string& status);
  // Another node asks for the whole picture of a session: handed to the relay if it runs here.
  void RequestKeyframe(const std::string& session_id);

 private:
  struct Channel {
    std::mutex mutex;
    std::unique_ptr<LiveState> state;
    std::vector<std::weak_ptr<LiveViewer>> viewers;
    bool local = false;    // the session runs here (else 'state' is a mirror)
    bool removed = false;  // dropped from the map: a Join that raced it looks again
  };
  std::shared_ptr<Channel> Find(const std::string& session_id, bool create);
  static std::vector<std::shared_ptr<LiveViewer>> LiveViewers(Channel& channel);
  void Deliver(const std::string& session_id, Channel& channel, LiveDelta delta);

  LiveRelay* relay_ = nullptr;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Channel>> channels_;
};

}  // namespace pslam::server
