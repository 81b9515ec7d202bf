#pragma once
// Sites (a building, a floor) and their map library: versioned map_server maps, each a closed
// session's final map or an imported PGM + YAML. For the REST worker threads (blocks on storage).
#include <nlohmann/json.hpp>

#include <mutex>
#include <random>
#include <string>
#include <vector>

#include "service/mapping_service.hpp"
#include "storage/records.hpp"

namespace pslam::server {

class SiteService {
 public:
  explicit SiteService(MappingService& mapping);

  SiteRow CreateSite(const nlohmann::json& body);  // {"name": ...}
  SiteRow GetSite(const std::string& id);          // throws ApiError 404
  std::vector<SiteRow> ListSites(int limit, int offset, std::int64_t* total);
  std::vector<SiteMapRow> ListVersions(const std::string& site_id);
  // The next version of a site's map, from {"session_id"} (a closed session's final map) or from
  // {"yaml", "pgm_base64"} (an import, stored byte for byte); both take an optional "note".
  SiteMapRow AddVersion(const std::string& site_id, const nlohmann::json& body);
  // One version with its files (0: the latest); throws ApiError 404.
  SiteMapRow GetVersion(const std::string& site_id, std::int64_t version);

 private:
  SiteMapRow FromSession(const std::string& session_id);

  MappingService& mapping_;
  std::mutex mutex_;
  std::mt19937_64 id_rng_;
};

nlohmann::json SiteToJson(const SiteRow& row);
nlohmann::json SiteMapToJson(const SiteMapRow& row);

}  // namespace pslam::server
