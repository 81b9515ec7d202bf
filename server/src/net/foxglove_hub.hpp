#pragma once
// The Foxglove side of the live view: which running sessions offer which channels, and the
// clients of /foxglove. A session's channels are advertised when it first publishes and
// unadvertised when it ends. Each tick is encoded once for all clients (FoxgloveState), under the
// session's lock; delivery only posts to each client's strand, which keeps one pending message
// per channel, so a slow client never holds up the engine or other clients.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "net/beast.hpp"
#include "service/foxglove_state.hpp"

namespace pslam::server {

struct FoxgloveData {
  std::uint32_t channel = 0;
  std::uint64_t ns = 0;
  Bytes payload;
};

class FoxgloveViewer {
 public:
  virtual ~FoxgloveViewer() = default;
  // Called on any thread; implementations post and return.
  virtual void Advertise(std::vector<std::uint32_t> channels, Bytes message) = 0;
  virtual void Unadvertise(std::vector<std::uint32_t> channels, Bytes message) = 0;
  virtual void Deliver(std::shared_ptr<const std::vector<FoxgloveData>> data) = 0;
};

class FoxgloveHub {
 public:
  // Held-back messages are flushed when due (a session that went quiet still sends its last map):
  // the timers wait on 'io' (the network threads, which outlive every socket and hub), the
  // encoding runs on 'work'.
  FoxgloveHub(net::any_io_executor io, net::any_io_executor work) : timers_(std::move(io)), work_(std::move(work)) {}

  void Publish(const std::string& session_id, const LiveFrame& frame);
  void End(const std::string& session_id);
  // Registers 'viewer'; returns the channels offered now and their advertise message (null if
  // none), atomically with the registration: later changes reach the viewer as calls.
  std::pair<std::vector<std::uint32_t>, Bytes> Join(const std::shared_ptr<FoxgloveViewer>& viewer);
  void Leave(const FoxgloveViewer* viewer);
  // A channel's current message (encoding it if need be); nullopt if it has none or is not offered.
  std::optional<FoxgloveData> Latest(std::uint32_t channel);
  // Counts a client's subscription to a channel (+1) or its end (-1): only channels someone
  // subscribes to are encoded.
  void CountSubscriber(std::uint32_t channel, int delta);

 private:
  struct Session {
    explicit Session(std::string id, net::any_io_executor timers)
        : id(id), state(std::move(id)), timer(std::move(timers)) {}
    std::string id;
    std::uint32_t first_channel = 0;  // channel of topic t: first_channel + t
    std::mutex mutex;
    FoxgloveState state;
    net::steady_timer timer;
    bool timer_armed = false;
    bool ended = false;
  };
  std::shared_ptr<Session> FindOrAdvertise(const std::string& session_id);
  std::vector<std::shared_ptr<FoxgloveViewer>> Viewers();
  FoxgloveState::Listening ListeningTo(const Session& session);
  void Send(const Session& session, const std::vector<FoxgloveMessage>& messages);
  void ArmFlush(const std::shared_ptr<Session>& session);  // with session->mutex held
  void OnFlush(const std::shared_ptr<Session>& session);

  net::any_io_executor timers_;
  net::any_io_executor work_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  std::map<std::uint32_t, std::shared_ptr<Session>> by_channel_;  // first channel of each session
  std::vector<std::weak_ptr<FoxgloveViewer>> viewers_;
  std::map<std::uint32_t, int> subscribers_;  // channel -> subscriptions to it
  std::uint32_t next_channel_ = 1;
};

}  // namespace pslam::server
