#pragma once
// The service's view of a connected agent (implemented by the ingest WebSocket session). The
// service calls these from the storage and engine threads; implementations only post work to their
// own executor and never block.
#include <cstdint>
#include <string>

#include "model/hypothesis.hpp"

namespace pslam::server {

class AgentLink {
 public:
  virtual ~AgentLink() = default;
  // Every input with seq <= 'seq' is durably stored.
  virtual void SendAck(std::int64_t seq) = 0;
  virtual void SendTarget(const ExplorationTarget& target) = 0;
  // The filter caught up: an agent paused for back-pressure may be read again.
  virtual void Resume() = 0;
  // The session no longer takes this agent's inputs (closed, deleted, taken over by a newer
  // connection of the agent, or storage failed): send an error with 'code' and close.
  virtual void Disconnect(const std::string& code, const std::string& reason) = 0;
};

}  // namespace pslam::server
