#pragma once
// The SQL of sites and their versioned maps (schema/db/0003_sites.sql). Every value is a bound
// parameter, as in SessionRepository.
#include <optional>
#include <string>
#include <vector>

#include "storage/records.hpp"
#include "storage/database.hpp"

namespace pslam::server {

class SiteRepository {
 public:
  explicit SiteRepository(Database& db) : db_(db) {}

  void CreateSite(const SiteRow& row);
  std::optional<SiteRow> GetSite(const std::string& id);
  std::vector<SiteRow> ListSites(int limit, int offset);
  std::int64_t CountSites();

  // Stores 'row' as the site's next version (row.version is ignored) and returns that version.
  // Run it in the writer: versions are numbered under its single connection.
  std::int64_t AddMapVersion(SiteMapRow row);
  // Versions without their files, newest first.
  std::vector<SiteMapRow> ListMapVersions(const std::string& site_id);
  // One version with its files; version 0 is the latest.
  std::optional<SiteMapRow> GetMapVersion(const std::string& site_id, std::int64_t version);

 private:
  Database& db_;
};

}  // namespace pslam::server
