// GET /api/health, GET /api/version, GET /api/events.
#include "api/handlers.hpp"
#include "api/query.hpp"
#include "common/clock.hpp"
#include "service/api_error.hpp"
#include "service/ingest_codec.hpp"
#include "service/json_views.hpp"

namespace pslam::server {

nlohmann::json ParseJsonBody(const ApiRequest& request) {
  if (request.body.empty()) return nlohmann::json::object();
  nlohmann::json body = nlohmann::json::parse(request.body, nullptr, false);
  if (body.is_discarded()) throw ApiError::BadRequest("the body is not valid JSON");
  if (!body.is_object()) throw ApiError::BadRequest("the body must be a JSON object");
  return body;
}

std::string SessionIdParam(const ApiRequest& request) {
  const std::string& id = request.Param("id");
  bool ok = id.size() <= 64;
  for (char c : id) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_');
  if (!ok) throw ApiError::NotFound("no session '" + id.substr(0, 64) + "'");
  return id;
}

namespace {
// A failure this recent makes the server "degraded": long enough for a monitor polling every few
// tens of seconds to see it, short enough that a passed condition clears by itself.
constexpr std::chrono::seconds kHealthWindow{60};
}  // namespace

void AddSystemRoutes(Router& router, ApiContext& ctx) {
  router.Add("GET", "/api/health", Access::kNone, [&ctx](const ApiRequest&) {
    nlohmann::json reasons = nlohmann::json::array();
    if (auto failure = ctx.mapping.writer().failures().Within(kHealthWindow)) {
      reasons.push_back("storage writes are failing: " + *failure);
    }
    const WriterStats w = ctx.mapping.writer().stats();  // after the failures: the writer counts, then notes
    if (auto failure = ctx.mapping.engine_failures().Within(kHealthWindow)) {
      reasons.push_back("a session's engine failed: " + *failure);
    }
    nlohmann::json body = {{"status", reasons.empty() ? "ok" : "degraded"},
                           {"uptime_seconds", SecondsSince(ctx.started)},
                           {"running_sessions", ctx.mapping.running_sessions()},
                           {"viewers", ctx.viewer_count ? ctx.viewer_count() : 0},
                           {"agents", ctx.agent_count ? ctx.agent_count() : 0},
                           {"storage", {{"commits", w.commits}, {"failed_jobs", w.failed_jobs},
                                        {"queued", ctx.mapping.writer().queued()},
                                        {"last_commit_ms", w.last_commit_ms}, {"max_commit_ms", w.max_commit_ms}}}};
    if (!reasons.empty()) body["reasons"] = reasons;
    return JsonResponse(200, body.dump());
  });
  router.Add("GET", "/api/version", Access::kNone, [&ctx](const ApiRequest&) {
    nlohmann::json body = {{"server", "pslam-server"},
                           {"version", PSLAM_SERVER_VERSION},
                           {"ingest_protocol", kIngestProtocolVersion},
                           {"live_protocol", 1},
                           {"schema_version", ctx.mapping.writer().schema_version()}};
    return JsonResponse(200, body.dump());
  });
  router.Add("GET", "/api/events", Access::kRead, [&ctx](const ApiRequest& req) {
    const int limit = static_cast<int>(QueryInteger(req.query, "limit", 1, 1000).value_or(100));
    const int offset = static_cast<int>(QueryInteger(req.query, "offset", 0, 1 << 30).value_or(0));
    auto lease = ctx.mapping.reads().Acquire();
    nlohmann::json events = nlohmann::json::array();
    for (const EventRow& e : lease->repository().ListEvents(std::nullopt, limit, offset)) events.push_back(EventToJson(e));
    return JsonResponse(200, nlohmann::json{{"events", events}, {"limit", limit}, {"offset", offset}}.dump());
  });
}

}  // namespace pslam::server
