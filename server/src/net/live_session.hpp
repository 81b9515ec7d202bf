#pragma once
// One viewer's WebSocket on /api/sessions/{id}/live (schema/ws/live.md): a full snapshot on
// subscribe, then deltas. The outbound queue is bounded and coalescing: per tile only the latest
// frame waits, pose/particles/stats/exploration keep only their latest message, hypotheses their
// latest event, trajectory increments concatenate (and collapse into one full trajectory past a
// limit). A slow viewer thus receives fewer, fresher updates, and nothing it is sent can grow
// without bound.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "net/beast.hpp"
#include "net/hub.hpp"
#include "net/server_context.hpp"

namespace pslam::server {

class LiveSession : public LiveViewer, public Closable, public std::enable_shared_from_this<LiveSession> {
 public:
  LiveSession(tcp::socket&& socket, std::shared_ptr<ServerContext> context, std::string session_id, std::string token);
  ~LiveSession() override;
  void Run(http::request<http::string_body> upgrade);

  // LiveViewer / Closable (any thread).
  void Deliver(std::shared_ptr<const LiveDelta> delta) override;
  void SessionEnded(const std::string& status) override;
  void CloseForShutdown() override;

 private:
  void OnAccept(beast::error_code ec);
  void Subscribe();
  void Enqueue(std::vector<LiveMessage> messages);
  void Merge(const LiveDelta& delta);
  void Read();
  void OnRead(beast::error_code ec, std::size_t bytes);
  void Write();
  void OnWrite(beast::error_code ec, std::size_t bytes);
  void Close(websocket::close_code code, const std::string& reason);

  websocket::stream<beast::tcp_stream> ws_;
  std::shared_ptr<ServerContext> context_;
  const std::string session_id_;
  const std::string token_;  // for the per-token quota
  beast::flat_buffer buffer_;
  bool subscribed_ = false;

  // Pending output, in sending order: ordered messages (snapshot, session status), then the
  // latest-state slots, then trajectory, hypotheses and tiles.
  std::deque<LiveMessage> ordered_;
  Bytes pose_, scan_, stats_, exploration_, particles_;
  std::int64_t trajectory_first_ = 0;
  std::vector<TrajectoryRow> trajectory_;
  bool trajectory_resync_ = false;
  std::map<std::int64_t, Bytes> hypotheses_;
  std::map<TileKey, Bytes> tiles_;

  LiveMessage in_flight_;
  bool writing_ = false;
  std::optional<websocket::close_reason> close_;
  bool close_started_ = false;
  bool ended_ = false;
};

}  // namespace pslam::server
