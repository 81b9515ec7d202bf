// Sites and their map library: create and list sites, list a site's map versions, add one (from a
// closed session or by importing map_server files), and fetch one as PGM + YAML.
#include <cctype>

#include "api/handlers.hpp"
#include "api/query.hpp"
#include "service/api_error.hpp"
#include "service/site_service.hpp"

namespace pslam::server {
namespace {

constexpr long long kMaxPage = 1000;

std::string SiteIdParam(const ApiRequest& request) {
  const std::string& id = request.Param("site");
  bool ok = id.size() <= 64;
  for (char c : id) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_');
  if (!ok) throw ApiError::NotFound("no site '" + id.substr(0, 64) + "'");
  return id;
}

// A version number, or "latest" (0).
std::int64_t VersionParam(const ApiRequest& request) {
  const std::string& v = request.Param("version");
  return v == "latest" ? 0 : PathInteger(v, "version", 1, 1LL << 40);
}

ApiResponse File(std::string content_type, std::string body, const std::string& filename) {
  ApiResponse r{200, std::move(content_type), std::move(body), {}};
  r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + filename + "\"");
  return r;
}

}  // namespace

void AddSiteRoutes(Router& router, ApiContext& ctx) {
  router.Add("GET", "/api/sites", Access::kRead, [&ctx](const ApiRequest& req) {
    const int limit = static_cast<int>(QueryInteger(req.query, "limit", 1, kMaxPage).value_or(100));
    const int offset = static_cast<int>(QueryInteger(req.query, "offset", 0, 1 << 30).value_or(0));
    std::int64_t total = 0;
    nlohmann::json list = nlohmann::json::array();
    for (const SiteRow& row : ctx.sites.ListSites(limit, offset, &total)) list.push_back(SiteToJson(row));
    return JsonResponse(200, nlohmann::json{{"sites", list}, {"total", total}, {"limit", limit}, {"offset", offset}}.dump());
  });
  router.Add("POST", "/api/sites", Access::kWrite, [&ctx](const ApiRequest& req) {
    const SiteRow row = ctx.sites.CreateSite(ParseJsonBody(req));
    ApiResponse r = JsonResponse(201, SiteToJson(row).dump());
    r.headers.emplace_back("Location", "/api/sites/" + row.id);
    return r;
  });
  router.Add("GET", "/api/sites/{site}", Access::kRead, [&ctx](const ApiRequest& req) {
    return JsonResponse(200, SiteToJson(ctx.sites.GetSite(SiteIdParam(req))).dump());
  });
  router.Add("GET", "/api/sites/{site}/maps", Access::kRead, [&ctx](const ApiRequest& req) {
    const std::string site = SiteIdParam(req);
    nlohmann::json list = nlohmann::json::array();
    for (const SiteMapRow& row : ctx.sites.ListVersions(site)) list.push_back(SiteMapToJson(row));
    return JsonResponse(200, nlohmann::json{{"site_id", site}, {"maps", list}}.dump());
  });
  router.Add("POST", "/api/sites/{site}/maps", Access::kWrite, [&ctx](const ApiRequest& req) {
    const SiteMapRow row = ctx.sites.AddVersion(SiteIdParam(req), ParseJsonBody(req));
    ApiResponse r = JsonResponse(201, SiteMapToJson(row).dump());
    r.headers.emplace_back("Location", "/api/sites/" + row.site_id + "/maps/" + std::to_string(row.version));
    return r;
  });
  router.Add("GET", "/api/sites/{site}/maps/{version}", Access::kRead, [&ctx](const ApiRequest& req) {
    return JsonResponse(200, SiteMapToJson(ctx.sites.GetVersion(SiteIdParam(req), VersionParam(req))).dump());
  });
  // The files as stored: an imported map comes back byte for byte. Versions never change.
  router.Add("GET", "/api/sites/{site}/maps/{version}/map.pgm", Access::kRead, [&ctx](const ApiRequest& req) {
    SiteMapRow row = ctx.sites.GetVersion(SiteIdParam(req), VersionParam(req));
    return File("image/x-portable-graymap", std::move(row.pgm), "map.pgm");
  });
  router.Add("GET", "/api/sites/{site}/maps/{version}/map.yaml", Access::kRead, [&ctx](const ApiRequest& req) {
    SiteMapRow row = ctx.sites.GetVersion(SiteIdParam(req), VersionParam(req));
    return File("application/yaml", std::move(row.yaml), "map.yaml");
  });
}

}  // namespace pslam::server
