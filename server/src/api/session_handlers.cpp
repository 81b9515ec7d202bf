// Sessions: list, create, get, close, delete; a session's statistics, trajectory and events; the
// operator's exploration choice; a localizing session's pose.
#include "api/handlers.hpp"
#include "api/query.hpp"
#include "service/api_error.hpp"
#include "service/json_fields.hpp"
#include "service/json_views.hpp"

namespace pslam::server {
namespace {

constexpr long long kMaxPage = 1000;

nlohmann::json SessionWithLiveState(ApiContext& ctx, const SessionRow& row) {
  nlohmann::json j = SessionToJson(row);
  const auto rt = ctx.mapping.Running(row.id);
  j["running"] = rt != nullptr;
  // Where exploration stands: live from the engine, else as of the last checkpoint.
  const nlohmann::json stored = ParseStoredJson(row.stats_json);
  const std::string state = rt ? rt->engine->stats().exploration
                               : (stored.is_object() ? stored.value("exploration", std::string()) : std::string());
  j["exploration"] = state.empty() ? nlohmann::json() : nlohmann::json(state);
  return j;
}

SessionFilter ParseSessionFilter(const ApiRequest& req) {
  SessionFilter f;
  f.status = QueryChoice(req.query, "status", {"active", "closed", "failed"});
  f.source = QueryString(req.query, "source");
  f.robot_id = QueryString(req.query, "robot_id");
  f.name_contains = QueryString(req.query, "name");
  f.created_after = QueryNumber(req.query, "created_after");
  f.created_before = QueryNumber(req.query, "created_before");
  f.limit = static_cast<int>(QueryInteger(req.query, "limit", 1, kMaxPage).value_or(50));
  f.offset = static_cast<int>(QueryInteger(req.query, "offset", 0, 1 << 30).value_or(0));
  return f;
}

}  // namespace

void AddSessionRoutes(Router& router, ApiContext& ctx) {
  router.Add("GET", "/api/sessions", Access::kRead, [&ctx](const ApiRequest& req) {
    const SessionFilter f = ParseSessionFilter(req);
    const SessionPage page = ctx.mapping.ListSessions(f);
    nlohmann::json list = nlohmann::json::array();
    for (const SessionRow& row : page.sessions) list.push_back(SessionWithLiveState(ctx, row));
    return JsonResponse(200, nlohmann::json{{"sessions", list}, {"total", page.total}, {"limit", f.limit},
                                            {"offset", f.offset}}.dump());
  });
  router.Add("POST", "/api/sessions", Access::kWrite, [&ctx](const ApiRequest& req) {
    const SessionRow row = ctx.mapping.CreateSession(ParseJsonBody(req));
    ApiResponse r = JsonResponse(201, SessionWithLiveState(ctx, row).dump());
    r.headers.emplace_back("Location", "/api/sessions/" + row.id);
    return r;
  });
  router.Add("GET", "/api/sessions/{id}", Access::kRead, [&ctx](const ApiRequest& req) {
    return JsonResponse(200, SessionWithLiveState(ctx, ctx.mapping.GetSession(SessionIdParam(req))).dump());
  });
  router.Add("DELETE", "/api/sessions/{id}", Access::kWrite, [&ctx](const ApiRequest& req) {
    ctx.mapping.DeleteSession(SessionIdParam(req));
    return ApiResponse{204, "application/json", "", {}};
  });
  router.Add("POST", "/api/sessions/{id}/close", Access::kWrite, [&ctx](const ApiRequest& req) {
    return JsonResponse(200, SessionWithLiveState(ctx, ctx.mapping.CloseSession(SessionIdParam(req))).dump());
  });
  router.Add("GET", "/api/sessions/{id}/stats", Access::kRead, [&ctx](const ApiRequest& req) {
    return JsonResponse(200, ctx.mapping.Statistics(SessionIdParam(req)).dump());
  });
  router.Add("POST", "/api/sessions/{id}/exploration", Access::kWrite, [&ctx](const ApiRequest& req) {
    const std::string id = SessionIdParam(req);
    const nlohmann::json body = ParseJsonBody(req);
    JsonFields f(body, "exploration");
    const auto verify = f.Bool("verify_predictions");
    f.RejectUnknown();
    if (!verify) f.Fail("verify_predictions", "is required (true or false)");
    ctx.mapping.SetVerifyPredicted(id, *verify);
    return JsonResponse(200, nlohmann::json{{"session_id", id}, {"verify_predictions", *verify}}.dump());
  });
  router.Add("POST", "/api/sessions/{id}/initial_pose", Access::kWrite, [&ctx](const ApiRequest& req) {
    const std::string id = SessionIdParam(req);
    const InitialPose pose = ctx.mapping.SetInitialPose(id, ParseJsonBody(req));
    return JsonResponse(200, nlohmann::json{{"session_id", id}, {"initial_pose", InitialPoseToJson(pose)}}.dump());
  });
  router.Add("GET", "/api/sessions/{id}/trajectory", Access::kRead, [&ctx](const ApiRequest& req) {
    const std::string id = SessionIdParam(req);
    ctx.mapping.GetSession(id);  // 404 for an unknown session rather than an empty list
    const long long from = QueryInteger(req.query, "from", 0, 1LL << 40).value_or(0);
    const int limit = static_cast<int>(QueryInteger(req.query, "limit", 1, 1 << 20).value_or(100000));
    auto lease = ctx.mapping.reads().Acquire();
    const auto rows = lease->repository().LoadTrajectory(id, from, limit);
    return JsonResponse(200, nlohmann::json{{"session_id", id}, {"from", from}, {"poses", TrajectoryToJson(rows)}}.dump());
  });
  router.Add("GET", "/api/sessions/{id}/events", Access::kRead, [&ctx](const ApiRequest& req) {
    const std::string id = SessionIdParam(req);
    ctx.mapping.GetSession(id);
    const int limit = static_cast<int>(QueryInteger(req.query, "limit", 1, kMaxPage).value_or(100));
    const int offset = static_cast<int>(QueryInteger(req.query, "offset", 0, 1 << 30).value_or(0));
    auto lease = ctx.mapping.reads().Acquire();
    nlohmann::json events = nlohmann::json::array();
    for (const EventRow& e : lease->repository().ListEvents(id, limit, offset)) events.push_back(EventToJson(e));
    return JsonResponse(200, nlohmann::json{{"events", events}, {"limit", limit}, {"offset", offset}}.dump());
  });
}

}  // namespace pslam::server
