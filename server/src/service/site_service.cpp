#include "service/site_service.hpp"

#include <cinttypes>
#include <cstdio>

#include "common/base64.hpp"
#include "common/clock.hpp"
#include "pslam/io/map_io.hpp"
#include "service/api_error.hpp"
#include "service/json_fields.hpp"
#include "service/site_maps.hpp"
#include "storage/site_repository.hpp"

namespace pslam::server {
namespace {

constexpr std::size_t kMaxYamlBytes = 64 * 1024;  // a map_server YAML is a few lines

// The image's size and placement, as map.pgm renders the grid's known cells.
void Describe(const OccupancyGrid& grid, SiteMapRow& row) {
  const MapImage image = RenderMapImage(grid);
  row.resolution = image.resolution;
  row.width = image.width;
  row.height = image.height;
  row.origin_x = image.origin.x();
  row.origin_y = image.origin.y();
}

}  // namespace

SiteService::SiteService(MappingService& mapping) : mapping_(mapping), id_rng_(std::random_device{}()) {}

SiteRow SiteService::CreateSite(const nlohmann::json& body) {
  JsonFields f(body, "site");
  SiteRow row;
  row.name = f.RequiredString("name");
  f.RejectUnknown();
  if (row.name.empty()) f.Fail("name", "must not be empty");
  {
    std::lock_guard lock(mutex_);
    char id[32];
    std::snprintf(id, sizeof id, "site-%016" PRIx64, static_cast<std::uint64_t>(id_rng_()));
    row.id = id;
  }
  row.created_at = UnixNow();
  mapping_.writer().Execute([&row](SessionRepository& repo) { SiteRepository(repo.database()).CreateSite(row); });
  return GetSite(row.id);
}

SiteRow SiteService::GetSite(const std::string& id) {
  auto lease = mapping_.reads().Acquire();
  auto row = SiteRepository(lease->repository().database()).GetSite(id);
  if (!row) throw ApiError::NotFound("no site '" + id.substr(0, 64) + "'");
  return *row;
}

std::vector<SiteRow> SiteService::ListSites(int limit, int offset, std::int64_t* total) {
  auto lease = mapping_.reads().Acquire();
  SiteRepository sites(lease->repository().database());
  *total = sites.CountSites();
  return sites.ListSites(limit, offset);
}

std::vector<SiteMapRow> SiteService::ListVersions(const std::string& site_id) {
  GetSite(site_id);
  auto lease = mapping_.reads().Acquire();
  return SiteRepository(lease->repository().database()).ListMapVersions(site_id);
}

SiteMapRow SiteService::FromSession(const std::string& session_id) {
  const SessionRow session = mapping_.GetSession(session_id);
  if (session.status != "closed") {
    throw ApiError::Conflict("session " + session_id + " is " + session.status + ": only a closed session's final map can become a site map");
  }
  const MapView view = mapping_.CurrentMap(session_id);
  if (!view.grid || view.grid->KnownBounds().empty()) throw ApiError::Conflict("session " + session_id + " mapped nothing");
  return SessionSiteMap(session_id, *view.grid);
}

SiteMapRow SiteService::AddVersion(const std::string& site_id, const nlohmann::json& body) {
  GetSite(site_id);
  JsonFields f(body, "map");
  const auto session_id = f.String("session_id", 64);
  const auto yaml = f.String("yaml", kMaxYamlBytes);
  const auto pgm_base64 = f.String("pgm_base64", std::string::npos);
  const std::string note = f.String("note", 1024).value_or("");
  f.RejectUnknown();
  SiteMapRow row;
  if (session_id) {
    if (yaml || pgm_base64) f.Fail("session_id", "is given with 'yaml' or 'pgm_base64': choose one source");
    row = FromSession(*session_id);
  } else {
    if (!yaml || !pgm_base64) f.Fail("yaml", "and 'pgm_base64' are required to import a map (or give 'session_id')");
    const auto pgm = Base64Decode(*pgm_base64);
    if (!pgm) f.Fail("pgm_base64", "is not base64 (RFC 4648, padded, no line breaks)");
    const OccupancyGrid grid = ParseSiteMapFiles(*yaml, *pgm, "uploaded map");
    row.source = "import";
    row.yaml = *yaml;
    row.pgm = *pgm;
    Describe(grid, row);
  }
  row.site_id = site_id;
  row.note = note;
  row.created_at = UnixNow();
  std::int64_t version = 0;
  mapping_.writer().Execute([&](SessionRepository& repo) { version = SiteRepository(repo.database()).AddMapVersion(row); });
  mapping_.LogEvent(std::nullopt, "site_map_added",
                    {{"site_id", site_id}, {"version", version}, {"source", row.source},
                     {"session_id", row.session_id ? nlohmann::json(*row.session_id) : nlohmann::json()}});
  row.version = version;
  row.yaml.clear();
  row.pgm.clear();
  return row;
}

SiteMapRow SiteService::GetVersion(const std::string& site_id, std::int64_t version) {
  GetSite(site_id);
  auto lease = mapping_.reads().Acquire();
  auto row = SiteRepository(lease->repository().database()).GetMapVersion(site_id, version);
  if (!row) {
    throw ApiError::NotFound(version > 0 ? "site " + site_id + " has no map version " + std::to_string(version)
                                         : "site " + site_id + " has no map yet");
  }
  return *row;
}

nlohmann::json SiteToJson(const SiteRow& row) {
  return {{"id", row.id},
          {"name", row.name},
          {"created_at", row.created_at},
          {"versions", row.versions},
          {"latest_version", row.latest_version > 0 ? nlohmann::json(row.latest_version) : nlohmann::json()}};
}

nlohmann::json SiteMapToJson(const SiteMapRow& row) {
  return {{"site_id", row.site_id},
          {"version", row.version},
          {"created_at", row.created_at},
          {"source", row.source},
          {"session_id", row.session_id ? nlohmann::json(*row.session_id) : nlohmann::json()},
          {"extends_version", row.extends_version ? nlohmann::json(*row.extends_version) : nlohmann::json()},
          {"note", row.note},
          {"resolution", row.resolution},
          {"image", {{"width", row.width}, {"height", row.height}, {"origin", {row.origin_x, row.origin_y}}}}};
}

}  // namespace pslam::server
