// GET /api/cluster: the nodes of the fleet, their load and the sessions each runs.
#include "api/handlers.hpp"

namespace pslam::server {

void AddClusterRoutes(Router& router, ApiContext& ctx) {
  router.Add("GET", "/api/cluster", Access::kRead, [&ctx](const ApiRequest&) {
    nlohmann::json nodes = nlohmann::json::array();
    nlohmann::json body;
    if (!ctx.cluster) {
      nodes.push_back({{"node_id", "local"},
                       {"address", ctx.address},
                       {"alive", true},
                       {"heartbeat_age_seconds", 0.0},
                       {"running_sessions", ctx.mapping.running_sessions()},
                       {"max_sessions", ctx.mapping.options().max_running_sessions},
                       {"agents", ctx.agent_count ? ctx.agent_count() : 0},
                       {"viewers", ctx.viewer_count ? ctx.viewer_count() : 0},
                       {"sessions", ctx.mapping.running_session_ids()}});
      body = {{"mode", "single"}, {"node_id", "local"}, {"nodes", nodes}};
      return JsonResponse(200, body.dump());
    }
    const ClusterView view = ctx.cluster->View();
    std::map<std::string, nlohmann::json> sessions_of;
    nlohmann::json leases = nlohmann::json::array();
    for (const LeaseRow& l : view.leases) {
      const bool live = l.expires_in > 0;
      if (live) sessions_of[l.node_id].push_back(l.session_id);
      leases.push_back({{"session_id", l.session_id}, {"node_id", l.node_id}, {"epoch", l.epoch},
                        {"expires_in_seconds", l.expires_in}});
    }
    for (const NodeRow& n : view.nodes) {
      nodes.push_back({{"node_id", n.node_id},
                       {"address", n.address},
                       {"alive", n.heartbeat_age <= view.lease_seconds},
                       {"heartbeat_age_seconds", n.heartbeat_age},
                       {"running_sessions", n.running_sessions},
                       {"max_sessions", n.max_sessions},
                       {"agents", n.agents},
                       {"viewers", n.viewers},
                       {"sessions", sessions_of.count(n.node_id) ? sessions_of[n.node_id] : nlohmann::json::array()}});
    }
    body = {{"mode", "fleet"}, {"node_id", view.node_id}, {"lease_seconds", view.lease_seconds},
            {"nodes", nodes}, {"leases", leases}};
    return JsonResponse(200, body.dump());
  });
}

}  // namespace pslam::server
