#pragma once
// Site maps as the engines use them: a stored version's map_server files parsed into a grid (by
// the core's map_server reader), and the checks an uploaded map passes before it is stored.
#include <cstdint>
#include <memory>
#include <string>

#include <vector>

#include "engine/site_library.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "storage/read_pool.hpp"
#include "storage/records.hpp"

namespace pslam::server {

// Parses map_server files; throws ApiError 400 (code "bad_map") saying what is wrong. Only PGM
// images (P5 or P2) are taken: their size is bounded by their bytes, unlike compressed formats.
OccupancyGrid ParseSiteMapFiles(const std::string& yaml, const std::string& pgm, const std::string& name);

// A session's final map as a site map version made from it (source "session"): its map_server
// files and the image's size and placement; site, version, note and time are left to the caller.
SiteMapRow SessionSiteMap(const std::string& session_id, const OccupancyGrid& map);

// A stored version (0: the latest) as a grid; throws ApiError 404 for a missing site or version.
// 'version' is set to the version loaded.
std::shared_ptr<const OccupancyGrid> LoadSiteMap(ReadPool& reads, const std::string& site_id, std::int64_t& version);

// The site's latest 'count' versions as grids, newest first (none for a site without maps).
std::vector<SiteLibraryMap> LoadSiteLibrary(ReadPool& reads, const std::string& site_id, int count);

}  // namespace pslam::server
