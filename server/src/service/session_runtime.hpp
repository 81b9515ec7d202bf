#pragma once
// A session that is running: its engine and the bookkeeping of exactly-once ingest.
//
//   last_received  highest seq admitted (queued for storage), in order without gaps
//   last_committed highest seq durably stored, so acknowledged; the engine gets inputs in this order
//   engine->processed_seq() highest seq in the filter
//
// last_received - processed_seq is the work in flight; the ingest stops reading from the agent
// while it exceeds the limit, which is the back-pressure that keeps memory bounded.
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "engine/session_engine.hpp"
#include "model/input.hpp"
#include "model/session_settings.hpp"
#include "service/agent_link.hpp"

namespace pslam::server {

struct SessionRuntime {
  std::string id;
  std::string source;  // agent | api | replay
  SessionSettings settings;
  LaserGeometry laser;
  std::unique_ptr<SessionEngine> engine;
  std::int64_t lease_epoch = 0;  // a fleet node: the lease it runs the session under (0: no fleet)

  std::mutex mutex;  // guards everything below
  std::int64_t last_received = 0;
  std::int64_t last_committed = 0;
  std::optional<InputRecord> last_pose;  // seq, t and odometry of the last admitted input (no ranges)
  std::weak_ptr<AgentLink> agent;
  bool agent_waiting = false;   // the agent is paused until the engine catches up
  bool closing = false;
  std::condition_variable progress;  // notified as the engine processes inputs (replay feeders wait on it)
};

}  // namespace pslam::server
