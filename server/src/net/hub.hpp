#pragma once
// The live-view hub (Beast chat-multi's shared_state, per session): holds each running session's
// picture (LiveState) and its viewers. A frame is encoded once for all viewers, under the
// session's lock; delivery happens outside it and only posts to each viewer's strand, so a slow
// viewer never holds up the engine or the other viewers.
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

class Hub {
 public:
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

 private:
  struct Channel {
    std::mutex mutex;
    std::unique_ptr<LiveState> state;
    std::vector<std::weak_ptr<LiveViewer>> viewers;
  };
  std::shared_ptr<Channel> Find(const std::string& session_id, bool create);

  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Channel>> channels_;
};

}  // namespace pslam::server
