#pragma once
// One running session as Foxglove clients see it: the latest of each topic, encoded once for all
// clients. Engine ticks bring changes; a topic's message goes out when it changed, and the heavy
// ones at most once per their period (the whole map, the whole trajectory and the prediction
// overlay every 2 s, the particle cloud every 0.5 s), the last change held back until then. A
// client that subscribes gets the topic's current message.
#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/engine_output.hpp"
#include "service/foxglove_codec.hpp"
#include "service/live_codec.hpp"

namespace pslam::server {

struct FoxgloveMessage {
  FoxgloveTopic topic = FoxgloveTopic::kMap;
  std::uint64_t ns = 0;  // log time: the server's clock when the tick was published
  Bytes payload;
};

class FoxgloveState {
 public:
  using Clock = std::chrono::steady_clock;
  explicit FoxgloveState(std::string session_id) : session_id_(std::move(session_id)) {}

  // Which topics someone subscribes to: only those are encoded as they change.
  using Listening = std::array<bool, kFoxgloveTopics.size()>;

  // Takes in a tick; returns the messages of listened-to topics that are due now.
  std::vector<FoxgloveMessage> Apply(const LiveFrame& frame, std::uint64_t ns, Clock::time_point now,
                                     const Listening& listening);
  // The held-back messages that are due at 'now' (those nobody listens to are only marked sent).
  std::vector<FoxgloveMessage> Flush(Clock::time_point now, const Listening& listening);
  // When the next held-back message is due; nullopt if none waits.
  std::optional<Clock::time_point> NextDue() const;
  // The topic's current message (encoded now if it changed since), or nullopt before the first.
  std::optional<FoxgloveMessage> Latest(FoxgloveTopic topic);

  static Clock::duration Period(FoxgloveTopic topic);

 private:
  struct Slot {
    bool has_data = false;  // the topic has had a value
    bool stale = false;     // 'cached' is older than the value
    bool unsent = false;    // changed since the last fan-out
    std::uint64_t ns = 0;   // of the value
    Bytes cached;
    Clock::time_point last_sent{};
  };
  Slot& SlotOf(FoxgloveTopic t) { return slots_[static_cast<std::size_t>(t)]; }
  void Changed(FoxgloveTopic t, std::uint64_t ns);
  Bytes Encode(FoxgloveTopic t) const;
  std::vector<FoxgloveMessage> Due(Clock::time_point now, const Listening& listening);

  std::string session_id_;
  std::array<Slot, kFoxgloveTopics.size()> slots_;
  // The latest values, which the payloads are made of.
  std::shared_ptr<const OccupancyGrid> map_;
  std::optional<Pose2D> pose_;
  std::shared_ptr<const LaserScan> scan_;
  Pose2D scan_pose_;
  std::int64_t scan_seq_ = -1;
  std::vector<Pose2D> trajectory_;
  std::vector<Pose2D> particles_;
  EngineStats stats_;
  std::vector<std::array<double, 2>> frontiers_;
  std::optional<ExplorationTarget> target_;
  double resolution_ = 0.05;
  std::map<std::int64_t, HypothesisRecord> pending_;  // pending predictions, with their cells
};

}  // namespace pslam::server
