// POST /api/replays: a stored session or a CARMEN log run again as a new session.
#include "api/handlers.hpp"
#include "service/json_views.hpp"

namespace pslam::server {

void AddReplayRoutes(Router& router, ApiContext& ctx) {
  router.Add("POST", "/api/replays", Access::kWrite, [&ctx](const ApiRequest& req) {
    const SessionRow row = ctx.replay.Start(ParseJsonBody(req));
    nlohmann::json j = SessionToJson(row);
    j["running"] = true;
    ApiResponse r = JsonResponse(201, j.dump());
    r.headers.emplace_back("Location", "/api/sessions/" + row.id);
    return r;
  });
}

}  // namespace pslam::server
