// POST /api/replays: a stored session or a CARMEN log run again as a new session; GET
// /api/replays/files: what the replay directory offers.
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
  router.Add("GET", "/api/replays/files", Access::kRead, [&ctx](const ApiRequest&) {
    nlohmann::json files = nlohmann::json::array();
    for (const ReplayFile& f : ctx.replay.Files()) files.push_back({{"name", f.name}, {"bytes", f.bytes}, {"kind", f.kind}});
    return JsonResponse(200, nlohmann::json{{"files", files}}.dump());
  });
}

}  // namespace pslam::server
