#include "storage/site_repository.hpp"

namespace pslam::server {
namespace {

constexpr const char* kSiteColumns =
    "id, name, created_at, (SELECT COUNT(*) FROM site_maps WHERE site_id = sites.id), "
    "(SELECT COALESCE(MAX(version), 0) FROM site_maps WHERE site_id = sites.id)";

SiteRow ReadSite(const Statement& s) { return {s.Text(0), s.Text(1), s.Double(2), s.Int64(3), s.Int64(4)}; }

constexpr const char* kVersionColumns =
    "site_id, version, created_at, source, session_id, note, resolution, width, height, origin_x, origin_y, "
    "extends_version";

SiteMapRow ReadVersion(const Statement& s) {
  SiteMapRow row;
  row.site_id = s.Text(0);
  row.version = s.Int64(1);
  row.created_at = s.Double(2);
  row.source = s.Text(3);
  if (!s.IsNull(4)) row.session_id = s.Text(4);
  row.note = s.Text(5);
  row.resolution = s.Double(6);
  row.width = s.Int(7);
  row.height = s.Int(8);
  row.origin_x = s.Double(9);
  row.origin_y = s.Double(10);
  if (!s.IsNull(11)) row.extends_version = s.Int64(11);
  return row;
}

}  // namespace

void SiteRepository::CreateSite(const SiteRow& row) {
  db_.Prepare("INSERT INTO sites (id, name, created_at) VALUES (?, ?, ?)").BindAll(row.id, row.name, row.created_at).Run();
}

std::optional<SiteRow> SiteRepository::GetSite(const std::string& id) {
  Statement s = db_.Prepare(std::string("SELECT ") + kSiteColumns + " FROM sites WHERE id = ?");
  s.Bind(1, id);
  if (!s.Step()) return std::nullopt;
  return ReadSite(s);
}

std::vector<SiteRow> SiteRepository::ListSites(int limit, int offset) {
  Statement s = db_.Prepare(std::string("SELECT ") + kSiteColumns + " FROM sites ORDER BY created_at, id LIMIT ? OFFSET ?");
  s.BindAll(limit, offset);
  std::vector<SiteRow> out;
  while (s.Step()) out.push_back(ReadSite(s));
  return out;
}

std::int64_t SiteRepository::CountSites() {
  Statement s = db_.Prepare("SELECT COUNT(*) FROM sites");
  s.Step();
  return s.Int64(0);
}

std::int64_t SiteRepository::AddMapVersion(SiteMapRow row) {
  Statement next = db_.Prepare("SELECT COALESCE(MAX(version), 0) + 1 FROM site_maps WHERE site_id = ?");
  next.Bind(1, row.site_id);
  next.Step();
  row.version = next.Int64(0);
  const std::span<const std::uint8_t> pgm(reinterpret_cast<const std::uint8_t*>(row.pgm.data()), row.pgm.size());
  db_.Prepare(
         "INSERT INTO site_maps (site_id, version, created_at, source, session_id, note, resolution, width, height, "
         "origin_x, origin_y, extends_version, yaml, pgm) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)")
      .BindAll(row.site_id, row.version, row.created_at, row.source, row.session_id, row.note, row.resolution, row.width,
               row.height, row.origin_x, row.origin_y, row.extends_version, row.yaml, pgm)
      .Run();
  return row.version;
}

std::vector<SiteMapRow> SiteRepository::ListMapVersions(const std::string& site_id) {
  Statement s = db_.Prepare(std::string("SELECT ") + kVersionColumns +
                            " FROM site_maps WHERE site_id = ? ORDER BY version DESC");
  s.Bind(1, site_id);
  std::vector<SiteMapRow> out;
  while (s.Step()) out.push_back(ReadVersion(s));
  return out;
}

std::optional<SiteMapRow> SiteRepository::GetMapVersion(const std::string& site_id, std::int64_t version) {
  Statement s = db_.Prepare(std::string("SELECT ") + kVersionColumns + ", yaml, pgm FROM site_maps WHERE site_id = ? " +
                            (version > 0 ? "AND version = ?" : "ORDER BY version DESC LIMIT 1"));
  s.Bind(1, site_id);
  if (version > 0) s.Bind(2, version);
  if (!s.Step()) return std::nullopt;
  SiteMapRow row = ReadVersion(s);
  row.yaml = s.Text(12);
  const std::vector<std::uint8_t> pgm = s.Blob(13);
  row.pgm.assign(pgm.begin(), pgm.end());
  return row;
}

}  // namespace pslam::server
