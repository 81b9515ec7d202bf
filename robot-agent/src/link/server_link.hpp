#pragma once
// The agent's WebSocket client for the ingest protocol (schema/ws/ingest.md). It runs on its own
// thread and only ever reads the spool: hello -> welcome -> stream every unacknowledged record in
// seq order -> drop records as cumulative acks arrive. Network loss is normal: on any failure it
// reconnects with capped exponential back-off, resumes its session and resends from the server's
// last_acked_seq. A fleet node may redirect it to the node that runs its session; a node that cannot
// be reached is followed by the next one it knows. Refusals are reported plainly: a transient one (the server is full) is retried,
// a permanent one (token refused, hello refused, the session failed) stops the link.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "link/messages.hpp"
#include "link/spool.hpp"

namespace pslam::agent {

struct ServerLinkOptions {
  std::string host;
  std::string port;
  // Further nodes of a fleet (HOST:PORT), tried in turn while the current one cannot be reached.
  std::vector<std::string> other_servers;
  std::string token;                  // sent as "Authorization: Bearer <token>"
  std::string path = "/api/ingest";
  bool binary_scans = true;           // scans as binary frames (48 + 4n bytes) rather than JSON
  // Sent but not yet acknowledged messages. pslam-server pauses an agent whose inputs run more than
  // 256 ahead of its filter; staying within that avoids provoking the pause.
  std::size_t max_in_flight = 256;
  double backoff_initial_s = 0.25;
  double backoff_max_s = 2.0;         // a robot on a LAN: retrying every 2 s costs one SYN
  double connect_timeout_s = 5.0;
  double idle_timeout_s = 4.0;        // Beast pings at half of this; no reply means a dead link
  std::filesystem::path session_file; // where the session id and seq base are kept
};

enum class LinkState { kDisconnected, kConnecting, kStreaming, kRefused };
// Why the link gave up: the token, or the session (a refused hello, a failed session).
enum class RefusalKind { kToken, kSession };

struct LinkStatus {
  LinkState state = LinkState::kDisconnected;
  double last_server_message_time = 0.0;  // AgentClock time of the last frame from the server
  std::uint64_t sent = 0;                 // data messages written to the socket (including resends)
  std::uint64_t resent = 0;               // of which were resends after a reconnect
  std::uint64_t acked_wire_seq = 0;
  std::size_t connections = 0;            // successful welcomes
  std::size_t failures = 0;
  std::size_t server_errors = 0;          // `error` messages received
  std::string session_id;
  std::string last_error;
};

class ServerLink {
 public:
  // 'spool' must outlive the link. 'hello' is sent on every connection with its session field set
  // by the link.
  ServerLink(ServerLinkOptions options, Spool& spool, HelloMessage hello);
  ~ServerLink();
  ServerLink(const ServerLink&) = delete;
  ServerLink& operator=(const ServerLink&) = delete;

  void Start();
  // Closes the connection and joins the thread. Idempotent.
  void Stop();
  // New records were appended to the spool (cheap; call after every append).
  void Notify();

  LinkStatus status() const;
  // The latest `target` from the server, once.
  std::optional<TargetMessage> TakeTarget();
  // Set when the server refused the agent for good; the message says what to do.
  std::optional<std::string> refusal() const;
  std::optional<RefusalKind> refusal_kind() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pslam::agent
