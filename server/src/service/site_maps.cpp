#include "service/site_maps.hpp"

#include <optional>
#include <stdexcept>

#include "pslam/io/map_io.hpp"
#include "service/api_error.hpp"
#include "storage/site_repository.hpp"

namespace pslam::server {

OccupancyGrid ParseSiteMapFiles(const std::string& yaml, const std::string& pgm, const std::string& name) {
  if (pgm.size() < 2 || pgm[0] != 'P' || (pgm[1] != '5' && pgm[1] != '2')) {
    throw ApiError(400, "bad_map", name + ": the image is not a PGM (P5 or P2)");
  }
  std::optional<OccupancyGrid> grid;
  try {
    grid.emplace(ParseMap(yaml, pgm, name));
  } catch (const std::runtime_error& e) {
    throw ApiError(400, "bad_map", e.what());
  }
  if (grid->KnownBounds().empty()) throw ApiError(400, "bad_map", name + ": the map has no known cell");
  return std::move(*grid);
}

SiteMapRow SessionSiteMap(const std::string& session_id, const OccupancyGrid& map) {
  const MapImage image = RenderMapImage(map);
  SiteMapRow row;
  row.source = "session";
  row.session_id = session_id;
  row.pgm = MapPgmBytes(image);
  row.yaml = MapYamlText(image, "map.pgm");
  row.resolution = image.resolution;
  row.width = image.width;
  row.height = image.height;
  row.origin_x = image.origin.x();
  row.origin_y = image.origin.y();
  return row;
}

std::shared_ptr<const OccupancyGrid> LoadSiteMap(ReadPool& reads, const std::string& site_id, std::int64_t& version) {
  std::optional<SiteMapRow> row;
  {
    auto lease = reads.Acquire();
    SiteRepository sites(lease->repository().database());
    if (!sites.GetSite(site_id)) throw ApiError::NotFound("no site '" + site_id.substr(0, 64) + "'");
    row = sites.GetMapVersion(site_id, version);
  }
  if (!row) {
    throw ApiError::NotFound(version > 0 ? "site " + site_id + " has no map version " + std::to_string(version)
                                         : "site " + site_id + " has no map yet");
  }
  version = row->version;
  // Stored versions passed ParseSiteMapFiles; one that no longer parses is a damaged database.
  return std::make_shared<const OccupancyGrid>(ParseMap(row->yaml, row->pgm, site_id + " version " + std::to_string(version)));
}

std::vector<SiteLibraryMap> LoadSiteLibrary(ReadPool& reads, const std::string& site_id, int count) {
  std::vector<SiteMapRow> rows;
  {
    auto lease = reads.Acquire();
    SiteRepository sites(lease->repository().database());
    for (const SiteMapRow& listed : sites.ListMapVersions(site_id)) {
      if (static_cast<int>(rows.size()) >= count) break;
      if (auto row = sites.GetMapVersion(site_id, listed.version)) rows.push_back(std::move(*row));
    }
  }
  std::vector<SiteLibraryMap> library;
  for (const SiteMapRow& row : rows) {
    const std::string name = site_id + " version " + std::to_string(row.version);
    library.push_back({site_id, row.version, std::make_shared<const OccupancyGrid>(ParseMap(row.yaml, row.pgm, name))});
  }
  return library;
}

}  // namespace pslam::server
