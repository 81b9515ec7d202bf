#pragma once
// The site's other maps, searched by a mapping session's structure predictor for references
// (pslam/predict/library_map.hpp): another floor of the same plan, an earlier map of a wing.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/library_map.hpp"

namespace pslam::server {

// A session loads the latest this many versions of its site at start: each costs its grid and
// features in memory and up to max_reference_corners alignments per prediction.
inline constexpr int kSiteLibraryVersions = 3;

struct SiteLibraryMap {
  std::string site;
  std::int64_t version = 0;
  std::shared_ptr<const OccupancyGrid> map;
};

// What a session of a site starts with: in localize mode the site's map; in map mode the latest
// kSiteLibraryVersions versions for the predictor.
struct SiteMaps {
  std::shared_ptr<const OccupancyGrid> fixed_map;
  std::vector<SiteLibraryMap> library;
};

// The id a hypothesis names a library map by (Hypothesis::reference_map): "SITE/VERSION".
std::string LibraryMapId(const std::string& site, std::int64_t version);

// Extracts each map's features with 'options' (slow: run it on the session's thread).
MapLibrary BuildMapLibrary(const std::vector<SiteLibraryMap>& maps, const PredictorOptions& options);

}  // namespace pslam::server
