#include "engine/site_library.hpp"

#include <iostream>
#include <stdexcept>

namespace pslam::server {

std::string LibraryMapId(const std::string& site, std::int64_t version) {
  return site + "/" + std::to_string(version);
}

MapLibrary BuildMapLibrary(const std::vector<SiteLibraryMap>& maps, const PredictorOptions& options) {
  MapLibrary library;
  for (const SiteLibraryMap& m : maps) {
    try {
      library.push_back(MakeLibraryMap(LibraryMapId(m.site, m.version), *m.map, options));
    } catch (const std::invalid_argument& e) {  // too large to keep: predict without it
      std::cerr << "site library: " << e.what() << "; not searched\n";
    }
  }
  return library;
}

}  // namespace pslam::server
