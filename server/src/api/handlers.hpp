#pragma once
// REST endpoints (schema/openapi.yaml). Handlers are thin: parse the request, call a service,
// shape the JSON. They run on the HTTP worker pool, never on a network thread.
#include <chrono>
#include <functional>
#include <string>

#include "api/router.hpp"
#include "cluster/cluster_coordinator.hpp"
#include "service/mapping_service.hpp"
#include "service/replay_service.hpp"
#include "service/site_service.hpp"

namespace pslam::server {

struct ApiContext {
  MappingService& mapping;
  ReplayService& replay;
  SiteService& sites;
  std::chrono::steady_clock::time_point started;
  std::function<std::size_t()> viewer_count;
  std::function<std::size_t()> agent_count;
  ClusterCoordinator* cluster = nullptr;  // a fleet node; null for a single server
  std::string address;                    // HOST:PORT where this server listens (or is advertised)
};

void AddSystemRoutes(Router& router, ApiContext& context);
void AddSessionRoutes(Router& router, ApiContext& context);
void AddMapRoutes(Router& router, ApiContext& context);
void AddHypothesisRoutes(Router& router, ApiContext& context);
void AddReplayRoutes(Router& router, ApiContext& context);
void AddSiteRoutes(Router& router, ApiContext& context);
void AddClusterRoutes(Router& router, ApiContext& context);

// Parses a request body as a JSON object; throws ApiError 400 with the parser's complaint.
nlohmann::json ParseJsonBody(const ApiRequest& request);
// The session id from the path, checked for shape (so it never reaches SQL as something odd).
std::string SessionIdParam(const ApiRequest& request);

}  // namespace pslam::server
