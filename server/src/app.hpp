#pragma once
// Wires the server together (storage, services, hub, router, listener) and runs it until SIGINT or
// SIGTERM, then shuts down in order: stop accepting, close WebSockets, stop replays and engines
// (each writes a checkpoint), commit and checkpoint the database, stop the threads.
#include <memory>

#include "api/handlers.hpp"
#include "cluster/cluster_coordinator.hpp"
#include "common/result.hpp"
#include "config/server_options.hpp"
#include "net/beast.hpp"
#include "net/listener.hpp"
#include "net/live_fanout.hpp"
#include "net/server_context.hpp"
#include "service/mapping_service.hpp"
#include "service/replay_service.hpp"
#include "service/site_service.hpp"
#include "storage/read_pool.hpp"
#include "storage/storage_writer.hpp"

namespace pslam::server {

class App {
 public:
  static Result<std::unique_ptr<App>> Create(ServerOptions options);
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  // Serves until a signal; returns the process exit code.
  int Run();

 private:
  explicit App(ServerOptions options);
  void Shutdown();

  ServerOptions options_;
  std::unique_ptr<StorageWriter> writer_;
  std::unique_ptr<ReadPool> reads_;
  std::unique_ptr<ClusterCoordinator> cluster_;  // a fleet node; outlives the sessions' writes
  std::unique_ptr<MappingService> mapping_;
  std::unique_ptr<ReplayService> replay_;
  std::unique_ptr<SiteService> sites_;
  net::io_context ioc_;
  net::thread_pool workers_;
  std::shared_ptr<ServerContext> context_;
  std::unique_ptr<LiveFanout> fanout_;  // with --redis
  std::unique_ptr<ApiContext> api_;
  std::shared_ptr<Listener> listener_;
};

}  // namespace pslam::server
