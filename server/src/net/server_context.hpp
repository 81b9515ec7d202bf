#pragma once
// What every connection needs: limits, access checks, the router, static files, the hub, the
// mapping service and the worker pool that runs request handlers off the network threads. Also
// keeps track of open WebSockets, so a shutdown can close them with "going away".
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "api/access.hpp"
#include "api/router.hpp"
#include "net/beast.hpp"
#include "net/foxglove_hub.hpp"
#include "net/hub.hpp"
#include "net/static_files.hpp"
#include "service/mapping_service.hpp"

namespace pslam::server {

struct NetLimits {
  std::size_t max_body_bytes = 1 << 20;        // HTTP request bodies
  std::size_t max_message_bytes = 1 << 20;     // WebSocket messages from agents and viewers
  std::chrono::seconds http_timeout{30};       // reading a request, writing a response
  std::chrono::seconds hello_timeout{10};      // an agent socket must say hello within this
  // Open WebSockets, by kind and per token, so that neither viewers nor one token (the read-only
  // viewer token, say) can take every slot.
  std::size_t max_agent_websockets = 32;
  std::size_t max_viewer_websockets = 256;
  std::size_t max_websockets_per_token = 128;  // only for sockets that gave a token
};

enum class SocketKind { kAgent, kViewer };

class Closable {
 public:
  virtual ~Closable() = default;
  virtual void CloseForShutdown() = 0;  // posts a close with 1001 (going away)
  // An agent socket that has not said hello yet: the first to give way when its quota is full.
  virtual bool Silent() const { return false; }
  virtual void CloseSilent() {}  // posts the close of a socket that gave way
};

class ServerContext {
 public:
  ServerContext(NetLimits limits, TokenAuth auth, StaticFiles files, MappingService& mapping,
                net::thread_pool& workers, net::any_io_executor io)
      : limits(limits),
        auth(std::move(auth)),
        files(std::move(files)),
        foxglove(std::move(io), workers.get_executor()),
        mapping(mapping),
        workers(workers) {}

  // The access a request's token grants: "Authorization: Bearer T", or "?token=T" for clients that
  // cannot set headers (browsers opening a WebSocket).
  Access AccessOf(const http::request<http::string_body>& req, bool* token_given) const;
  static std::string TokenOf(const http::request<http::string_body>& req);
  // An HTTP request that is not a WebSocket upgrade: the API under /api/, static files elsewhere.
  http::response<http::string_body> HandleHttp(const http::request<http::string_body>& req, const std::string& remote);
  // Logs a refused request (stderr and the events table).
  void LogRefusal(const std::string& method, const std::string& path, const std::string& remote, int status);

  // Counts an open WebSocket against its quotas. When a quota is full, the oldest silent agent
  // socket in it gives way; if there is none, returns why the new socket is refused.
  std::optional<std::string> Track(const std::shared_ptr<Closable>& socket, SocketKind kind, const std::string& token);
  void CloseAll();
  std::size_t websockets();

  const NetLimits limits;
  const TokenAuth auth;
  Router router;
  const StaticFiles files;
  Hub hub;
  FoxgloveHub foxglove;
  MappingService& mapping;
  net::thread_pool& workers;
  std::atomic<std::size_t> agents{0};

 private:
  struct Tracked {
    std::weak_ptr<Closable> socket;
    SocketKind kind;
    std::string token;
  };
  std::mutex mutex_;
  std::vector<Tracked> sockets_;  // oldest first
};

http::response<http::string_body> ToBeastResponse(ApiResponse response, unsigned version, bool keep_alive, bool head);

}  // namespace pslam::server
