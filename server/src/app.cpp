#include "app.hpp"

#include <csignal>
#include <future>
#include <iostream>
#include <thread>

namespace pslam::server {

App::App(ServerOptions options)
    : options_(std::move(options)), ioc_(options_.io_threads), workers_(static_cast<std::size_t>(options_.http_workers)) {}

App::~App() { workers_.join(); }

Result<std::unique_ptr<App>> App::Create(ServerOptions options) {
  if (auto problem = ValidateOptions(options)) return Error{*problem};
  std::unique_ptr<App> app(new App(std::move(options)));
  const ServerOptions& o = app->options_;
  std::error_code ec;
  std::filesystem::create_directories(o.data_dir, ec);
  if (ec) return Error{"cannot create the data directory " + o.data_dir.string() + ": " + ec.message()};
  const StorageLocation storage = StorageOf(o);
  auto writer = StorageWriter::Open(storage);
  if (!writer) return Error{"storage: " + writer.error()};
  app->writer_ = std::move(writer.value());
  app->reads_ = std::make_unique<ReadPool>(storage);

  ServiceOptions service;
  service.defaults = o.session_defaults;
  service.limits = o.settings_limits;
  service.timing = o.timing;
  service.max_inflight = o.max_inflight_inputs;
  service.max_running_sessions = o.max_running_sessions;
  service.resume_on_restart = o.resume_on_restart;
  app->mapping_ = std::make_unique<MappingService>(service, *app->writer_, *app->reads_);
  app->replay_ = std::make_unique<ReplayService>(*app->mapping_, o.replay_dir);
  app->sites_ = std::make_unique<SiteService>(*app->mapping_);

  app->context_ = std::make_shared<ServerContext>(o.net, TokenAuth(o.agent_tokens, o.viewer_tokens),
                                                  StaticFiles(o.web_dir), *app->mapping_, app->workers_,
                                                  app->ioc_.get_executor());
  ServerContext* context = app->context_.get();
  if (o.redis_url) {
    app->fanout_ = std::make_unique<LiveFanout>(ParseRedisUrl(*o.redis_url).value(), context->hub);
    context->hub.SetRelay(app->fanout_.get());
  }
  app->mapping_->SetLiveSinks(
      [context](const std::string& id, std::shared_ptr<const LiveFrame> frame) {
        context->hub.Publish(id, *frame);
        context->foxglove.Publish(id, *frame);
      },
      [context](const std::string& id, const std::string& status) {
        context->hub.End(id, status);
        context->foxglove.End(id);
      });
  app->api_ = std::make_unique<ApiContext>(ApiContext{*app->mapping_, *app->replay_, *app->sites_, std::chrono::steady_clock::now(),
                                                      [context] { return context->hub.viewers(); },
                                                      [context] { return context->agents.load(); }, nullptr, ""});
  Router& router = app->context_->router;
  AddSystemRoutes(router, *app->api_);
  AddSessionRoutes(router, *app->api_);
  AddMapRoutes(router, *app->api_);
  AddHypothesisRoutes(router, *app->api_);
  AddReplayRoutes(router, *app->api_);
  AddSiteRoutes(router, *app->api_);
  AddClusterRoutes(router, *app->api_);
  router.SetRefusalLog([context](const ApiRequest& req, int status) {
    context->LogRefusal(req.method, req.path, req.remote, status);
  });

  beast::error_code address_error;
  const auto address = net::ip::make_address(o.host == "localhost" ? "127.0.0.1" : o.host, address_error);
  if (address_error) return Error{"--listen: '" + o.host + "' is not an IP address"};
  auto listener = Listener::Create(app->ioc_, tcp::endpoint(address, o.port), app->context_);
  if (!listener) return Error{listener.error()};
  app->listener_ = listener.value();
  const auto bound = app->listener_->local_endpoint();
  app->api_->address = bound.address().to_string() + ":" + std::to_string(bound.port());

  if (o.node_id) {
    ClusterOptions cluster{*o.node_id, o.advertise.value_or(app->api_->address), o.lease_seconds};
    MappingService* mapping = app->mapping_.get();
    ClusterCoordinator::Hooks hooks;
    hooks.load = [mapping, context] {
      return NodeLoad{static_cast<std::int64_t>(mapping->running_sessions()),
                      static_cast<std::int64_t>(mapping->options().max_running_sessions),
                      static_cast<std::int64_t>(context->agents.load()),
                      static_cast<std::int64_t>(context->hub.viewers())};
    };
    hooks.lost = [mapping](const std::string& id) { mapping->Abandon(id); };
    hooks.adopt = [mapping](const std::string& id, std::int64_t epoch) { mapping->Adopt(id, epoch); };
    hooks.hand_over = [mapping](const std::string& id) { return mapping->HandOver(id); };
    // Nothing runs yet, so the first takeover check (after one tick) finds this node idle.
    auto coordinator = ClusterCoordinator::Start(cluster, *o.postgres_url, std::move(hooks));
    if (!coordinator) return Error{coordinator.error()};
    app->cluster_ = std::move(coordinator.value());
    app->mapping_->SetCluster(app->cluster_.get());
    app->api_->cluster = app->cluster_.get();
    std::cout << "fleet node " << cluster.node_id << " at " << cluster.address << ", lease " << cluster.lease_seconds
              << " s" << std::endl;
  }
  try {
    app->mapping_->Recover();
  } catch (const std::exception& e) {
    return Error{std::string("resuming sessions failed: ") + e.what()};
  }
  return app;
}

int App::Run() {
  std::promise<int> stop;
  auto stopped = stop.get_future();
  net::signal_set signals(ioc_, SIGINT, SIGTERM);
  signals.async_wait([&stop](beast::error_code ec, int signal) {
    if (!ec) stop.set_value(signal);
  });
  listener_->Run();
  const auto endpoint = listener_->local_endpoint();
  std::cout << "listening on http://" << endpoint.address().to_string() << ":" << endpoint.port() << std::endl;
  std::vector<std::thread> threads;
  for (int i = 0; i < options_.io_threads; ++i) threads.emplace_back([this] { ioc_.run(); });
  const int signal = stopped.get();
  std::cerr << "signal " << signal << ": shutting down\n";
  Shutdown();
  ioc_.stop();
  for (auto& t : threads) t.join();
  std::cerr << "stopped\n";
  return 0;
}

void App::Shutdown() {
  if (cluster_) cluster_->Stop();  // no more takeovers; the leases hold until Leave or expiry
  listener_->Stop();
  context_->CloseAll();
  replay_->Shutdown();
  mapping_->Shutdown();  // engines stop after their current input and checkpoint
  writer_->Stop();       // commits what is queued, folds the WAL into the database
  if (fanout_) fanout_->Stop();  // after the engines: their sessions' ends go out
  if (cluster_) cluster_->Leave();  // the other nodes take the sessions over now
  // Give the close handshakes a moment to finish before the io threads stop.
  for (int i = 0; i < 20 && context_->websockets() > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
}

}  // namespace pslam::server
