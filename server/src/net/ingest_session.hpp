#pragma once
// One agent's WebSocket (schema/ws/ingest.md). Reads one message at a time on its strand: hello
// opens or resumes a session; odom and scan are admitted exactly once and acknowledged after the
// commit. Messages are read frame by frame so an oversize message is refused with an error before
// it is buffered. While the session's filter is too far behind, the session stops reading (TCP
// then pushes back on the agent) and resumes when the filter catches up. Meanwhile (a resumed
// session's rebuild can take a minute) it pings the agent every second: an agent hears nothing
// else, and would take the silence for a dead link.
//
// Outbound messages are few and bounded: acks coalesce into the latest, targets replace each
// other, errors beyond a small backlog are dropped.
#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "net/beast.hpp"
#include "net/server_context.hpp"
#include "service/agent_link.hpp"
#include "service/ingest_codec.hpp"

namespace pslam::server {

class IngestSession : public AgentLink, public Closable, public std::enable_shared_from_this<IngestSession> {
 public:
  IngestSession(tcp::socket&& socket, std::shared_ptr<ServerContext> context, Access access, std::string remote,
                std::string token);
  ~IngestSession() override;
  void Run(http::request<http::string_body> upgrade);

  // AgentLink (any thread).
  void SendAck(std::int64_t seq) override;
  void SendTarget(const ExplorationTarget& target) override;
  void Resume() override;
  void Disconnect(const std::string& code, const std::string& reason) override;
  // Closable (any thread).
  void CloseForShutdown() override;
  bool Silent() const override { return !greeted_; }
  void CloseSilent() override;

 private:
  void OnAccept(beast::error_code ec);
  void ReadMore();
  void OnRead(beast::error_code ec, std::size_t bytes);
  void HandleMessage();
  void HandleHello(HelloMessage hello);
  void OnOpened(MappingService::AgentOpen opened);
  void HandleInput(InputRecord input);
  void Send(std::string message);
  void CloseAfterSending(websocket::close_code code, const std::string& reason);
  void Write();
  void OnWrite(beast::error_code ec, std::size_t bytes);
  void KeepAliveWhilePaused();
  void OnEnded();
  void OnHelloDeadline(beast::error_code ec);
  void CloseUngreeted(const std::string& why);

  websocket::stream<beast::tcp_stream> ws_;
  std::shared_ptr<ServerContext> context_;
  const Access access_;
  const std::string remote_;
  const std::string token_;  // for the per-token quota
  beast::flat_buffer buffer_;
  net::steady_timer hello_deadline_;
  std::atomic<bool> greeted_{false};  // welcomed into a session
  bool hello_late_ = false;           // the deadline passed while a hello was being handled

  std::shared_ptr<SessionRuntime> runtime_;
  std::optional<LaserGeometry> laser_;
  bool reading_ = false;
  bool paused_ = false;         // back-pressure: waiting for the filter
  std::shared_ptr<IngestSession> paused_self_;  // keeps a paused session alive
  bool opening_ = false;        // a hello is being handled
  bool ended_ = false;

  std::deque<std::string> outbox_;
  std::optional<std::string> pending_target_;
  std::int64_t ack_wanted_ = 0, ack_sent_ = 0;
  std::string in_flight_;
  bool writing_ = false;
  std::optional<websocket::close_reason> close_;
  bool close_started_ = false;
  bool ping_wanted_ = false;
  net::steady_timer keepalive_;
};

}  // namespace pslam::server
