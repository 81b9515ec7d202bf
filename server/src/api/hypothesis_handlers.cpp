// A session's structure predictions: filtered list, one hypothesis with its status history, and
// its cells as a PNG overlay.
#include <sstream>

#include "api/handlers.hpp"
#include "api/query.hpp"
#include "service/api_error.hpp"
#include "service/json_views.hpp"
#include "service/map_export.hpp"

namespace pslam::server {
namespace {

HypothesisFilter ParseHypothesisFilter(const ApiRequest& req) {
  HypothesisFilter f;
  f.status = QueryChoice(req.query, "status", {"pending", "confirmed", "refuted", "expired"});
  f.min_psi = QueryNumber(req.query, "min_psi");
  f.t_from = QueryNumber(req.query, "from");
  f.t_to = QueryNumber(req.query, "to");
  if (const auto bbox = QueryString(req.query, "bbox")) {
    // "min_x,min_y,max_x,max_y" in metres.
    std::array<double, 4> box{};
    std::map<std::string, std::string> parts;
    std::stringstream in(*bbox);
    std::string part;
    int n = 0;
    while (std::getline(in, part, ',') && n < 5) parts["bbox[" + std::to_string(n++) + "]"] = part;
    if (n != 4) throw ApiError::BadRequest("bbox must be min_x,min_y,max_x,max_y");
    for (int i = 0; i < 4; ++i) box[static_cast<std::size_t>(i)] = *QueryNumber(parts, "bbox[" + std::to_string(i) + "]");
    if (box[0] > box[2] || box[1] > box[3]) throw ApiError::BadRequest("bbox: min must not exceed max");
    f.bbox = box;
  }
  f.limit = static_cast<int>(QueryInteger(req.query, "limit", 1, 1000).value_or(100));
  f.offset = static_cast<int>(QueryInteger(req.query, "offset", 0, 1 << 30).value_or(0));
  return f;
}

std::int64_t HypothesisIdParam(const ApiRequest& req) {
  return PathInteger(req.Param("hid"), "hypothesis id", 0, INT64_MAX);
}

HypothesisRecord HypothesisOrThrow(ApiContext& ctx, const std::string& id, std::int64_t hid) {
  auto lease = ctx.mapping.reads().Acquire();
  auto h = lease->repository().GetHypothesis(id, hid);
  if (!h) throw ApiError::NotFound("no hypothesis " + std::to_string(hid) + " in session " + id);
  return *h;
}

}  // namespace

void AddHypothesisRoutes(Router& router, ApiContext& ctx) {
  router.Add("GET", "/api/sessions/{id}/hypotheses", Access::kRead, [&ctx](const ApiRequest& req) {
    const std::string id = SessionIdParam(req);
    const HypothesisFilter f = ParseHypothesisFilter(req);
    ctx.mapping.GetSession(id);
    auto lease = ctx.mapping.reads().Acquire();
    const HypothesisPage page = lease->repository().QueryHypotheses(id, f);
    nlohmann::json list = nlohmann::json::array();
    for (const HypothesisRecord& h : page.hypotheses) list.push_back(HypothesisToJson(h, false));
    return JsonResponse(200, nlohmann::json{{"hypotheses", list}, {"total", page.total}, {"limit", f.limit},
                                            {"offset", f.offset}}.dump());
  });
  router.Add("GET", "/api/sessions/{id}/hypotheses/{hid}", Access::kRead, [&ctx](const ApiRequest& req) {
    const std::string id = SessionIdParam(req);
    const std::int64_t hid = HypothesisIdParam(req);
    nlohmann::json j = HypothesisToJson(HypothesisOrThrow(ctx, id, hid), /*with_cells=*/true);
    nlohmann::json history = nlohmann::json::array();
    auto lease = ctx.mapping.reads().Acquire();
    for (const HypothesisStatusRow& s : lease->repository().HypothesisHistory(id, hid)) {
      history.push_back({{"t", s.t}, {"status", s.status}, {"hit_ratio", s.hit_ratio}, {"psi_observed", s.psi_observed}});
    }
    j["history"] = std::move(history);
    return JsonResponse(200, j.dump());
  });
  router.Add("GET", "/api/sessions/{id}/hypotheses/{hid}/overlay.png", Access::kRead, [&ctx](const ApiRequest& req) {
    const std::string id = SessionIdParam(req);
    const HypothesisRecord h = HypothesisOrThrow(ctx, id, HypothesisIdParam(req));
    const double resolution =
        ParseStoredJson(ctx.mapping.GetSession(id).settings_json).value("resolution_meters", 0.05);
    const Overlay overlay = HypothesisOverlay(h, resolution);
    ApiResponse r{200, "image/png", overlay.png, {}};
    // Where to draw it: the world position of the image's lower-left corner, and metres per pixel.
    r.headers.emplace_back("X-Map-Origin", std::to_string(overlay.origin_x) + "," + std::to_string(overlay.origin_y));
    r.headers.emplace_back("X-Map-Resolution", std::to_string(resolution));
    return r;
  });
}

}  // namespace pslam::server
