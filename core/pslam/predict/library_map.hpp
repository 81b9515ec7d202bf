#pragma once
// A map of the site's library: another map of the same building (another floor of the same plan,
// an earlier map of a wing) that the structure predictor searches for references besides the map
// being built. Its features and match window depend on the map alone, so they are computed once
// here, not per prediction; the map itself is shared and never changes.
#include <memory>
#include <string>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/predict/features.hpp"
#include "pslam/predict/predictor_options.hpp"
#include "pslam/predict/region_matcher.hpp"

namespace pslam {

struct LibraryMap {
  std::string id;                             // how hypotheses name it (Hypothesis::reference_map)
  OccupancyGrid map;
  std::vector<Corner> corners;                // with at least one arm, strongest first
  std::shared_ptr<const MatchWindow> window;  // the whole known extent of 'map'
};

using MapLibrary = std::vector<std::shared_ptr<const LibraryMap>>;

// Rasterises 'map' over its known cells and extracts its features with the options the predictor
// will use (states, features, tolerance). Throws std::invalid_argument for an empty id or a map
// larger than kMaxLibraryMapCells.
std::shared_ptr<const LibraryMap> MakeLibraryMap(std::string id, OccupancyGrid map, const PredictorOptions& options);

// A bound on each library map's raster and window (bytes per cell: 2), so that a library cannot
// grow memory without bound: 16 M cells, 200 m x 200 m at 5 cm.
inline constexpr long long kMaxLibraryMapCells = 16LL * 1024 * 1024;

}  // namespace pslam
