// A session's map: JSON metadata, PNG, map_server PGM + YAML, and single tiles.
#include "api/handlers.hpp"
#include "api/query.hpp"
#include "service/api_error.hpp"
#include "service/map_export.hpp"

namespace pslam::server {
namespace {

// The current map; an empty grid of the session's resolution if nothing is mapped yet.
std::shared_ptr<const OccupancyGrid> MapOf(ApiContext& ctx, const std::string& id, bool* live) {
  const MapView view = ctx.mapping.CurrentMap(id);
  *live = view.live;
  return view.grid ? view.grid : std::make_shared<const OccupancyGrid>(view.resolution);
}

ApiResponse Binary(std::string content_type, std::string body, bool live) {
  ApiResponse r{200, std::move(content_type), std::move(body), {}};
  // A running session's map changes by the second; a closed one never does.
  r.headers.emplace_back("Cache-Control", live ? "no-store" : "private, max-age=60");
  return r;
}

int TileIndex(const ApiRequest& req, const std::string& name) {
  std::map<std::string, std::string> value = {{name, req.Param(name)}};
  return static_cast<int>(*QueryInteger(value, name, -(1 << 24), 1 << 24));
}

}  // namespace

void AddMapRoutes(Router& router, ApiContext& ctx) {
  router.Add("GET", "/api/sessions/{id}/map", Access::kRead, [&ctx](const ApiRequest& req) {
    bool live = false;
    const auto grid = MapOf(ctx, SessionIdParam(req), &live);
    return JsonResponse(200, MapMetadata(*grid, live).dump());
  });
  router.Add("GET", "/api/sessions/{id}/map.png", Access::kRead, [&ctx](const ApiRequest& req) {
    bool live = false;
    const auto grid = MapOf(ctx, SessionIdParam(req), &live);
    return Binary("image/png", MapPng(*grid), live);
  });
  router.Add("GET", "/api/sessions/{id}/map.pgm", Access::kRead, [&ctx](const ApiRequest& req) {
    bool live = false;
    const auto grid = MapOf(ctx, SessionIdParam(req), &live);
    ApiResponse r = Binary("image/x-portable-graymap", MapPgm(*grid), live);
    r.headers.emplace_back("Content-Disposition", "attachment; filename=\"map.pgm\"");
    return r;
  });
  router.Add("GET", "/api/sessions/{id}/map.yaml", Access::kRead, [&ctx](const ApiRequest& req) {
    bool live = false;
    const auto grid = MapOf(ctx, SessionIdParam(req), &live);
    ApiResponse r = Binary("application/yaml", MapYaml(*grid, "map.pgm"), live);
    r.headers.emplace_back("Content-Disposition", "attachment; filename=\"map.yaml\"");
    return r;
  });
  router.Add("GET", "/api/sessions/{id}/map/tiles/{tx}/{ty}", Access::kRead, [&ctx](const ApiRequest& req) {
    const int tx = TileIndex(req, "tx"), ty = TileIndex(req, "ty");
    bool live = false;
    const auto grid = MapOf(ctx, SessionIdParam(req), &live);
    const auto tile = MapTile(*grid, tx, ty);
    if (!tile) throw ApiError::NotFound("no tile (" + std::to_string(tx) + ", " + std::to_string(ty) + ")");
    return Binary("application/octet-stream", **tile, live);
  });
}

}  // namespace pslam::server
