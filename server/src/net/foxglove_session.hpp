#pragma once
// One client's WebSocket on /foxglove, speaking the Foxglove WebSocket protocol (subprotocol
// foxglove.sdk.v1 or foxglove.websocket.v1; schema/ws/foxglove.md): serverInfo and the running
// sessions' channels on connect, then message data for the client's subscriptions. Outbound is
// bounded: control messages (advertise, unadvertise, status) queue in order, status messages up to
// a cap; message data keeps one pending message per channel, the latest. A client's mistakes get
// a status message and change nothing else.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "net/beast.hpp"
#include "net/foxglove_hub.hpp"
#include "net/server_context.hpp"

namespace pslam::server {

// The subprotocol to answer with: the first of the client's offers that we speak, if any.
std::optional<std::string> ChooseFoxgloveSubprotocol(const http::request<http::string_body>& upgrade);

class FoxgloveSession : public FoxgloveViewer, public Closable, public std::enable_shared_from_this<FoxgloveSession> {
 public:
  FoxgloveSession(tcp::socket&& socket, std::shared_ptr<ServerContext> context, std::string token,
                  std::string subprotocol);
  ~FoxgloveSession() override;
  void Run(http::request<http::string_body> upgrade);

  // FoxgloveViewer / Closable (any thread).
  void Advertise(std::vector<std::uint32_t> channels, Bytes message) override;
  void Unadvertise(std::vector<std::uint32_t> channels, Bytes message) override;
  void Deliver(std::shared_ptr<const std::vector<FoxgloveData>> data) override;
  void CloseForShutdown() override;

 private:
  void OnAccept(beast::error_code ec);
  void Read();
  void OnRead(beast::error_code ec, std::size_t bytes);
  void Handle(const std::string& text);
  void Subscribe(const nlohmann::json& request);
  void Unsubscribe(const nlohmann::json& request);
  void Status(int level, const std::string& message);
  void Queue(Bytes message);
  void Write();
  void OnWrite(beast::error_code ec, std::size_t bytes);
  void Close(websocket::close_code code, const std::string& reason);
  void Stop();

  websocket::stream<beast::tcp_stream> ws_;
  std::shared_ptr<ServerContext> context_;
  const std::string token_;  // for the per-token quota
  const std::string subprotocol_;
  beast::flat_buffer buffer_;
  bool joined_ = false;

  std::set<std::uint32_t> advertised_;                   // channels this client may subscribe to
  std::map<std::uint32_t, std::uint32_t> subscriptions_;  // subscription id -> channel
  std::map<std::uint32_t, std::uint32_t> by_channel_;     // channel -> subscription id

  std::deque<std::pair<Bytes, bool>> ordered_;  // text messages in order; whether each is a status
  std::size_t statuses_queued_ = 0;
  std::map<std::uint32_t, FoxgloveData> pending_;  // channel -> its latest message data
  std::uint32_t last_channel_sent_ = 0;            // round robin over the channels

  Bytes in_flight_;
  std::array<std::uint8_t, kFoxgloveMessageHeader> header_{};
  bool writing_ = false;
  std::optional<websocket::close_reason> close_;
  bool close_started_ = false;
  bool ended_ = false;
};

}  // namespace pslam::server
