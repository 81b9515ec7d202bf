#include "pslam/predict/library_map.hpp"

#include <stdexcept>
#include <utility>

#include "pslam/predict/map_raster.hpp"

namespace pslam {

std::shared_ptr<const LibraryMap> MakeLibraryMap(std::string id, OccupancyGrid map, const PredictorOptions& options) {
  if (id.empty()) throw std::invalid_argument("library map: empty id");
  const CellBox box = map.KnownBounds();
  if (!box.empty() && static_cast<long long>(box.width()) * box.height() > kMaxLibraryMapCells) {
    throw std::invalid_argument("library map '" + id + "': larger than " + std::to_string(kMaxLibraryMapCells) +
                                " cells");
  }
  auto library = std::make_shared<LibraryMap>();
  library->id = std::move(id);
  const CellClassifier classify(options.states);
  const CellRaster raster = RasterizeRegion(map, box, classify);
  library->corners = ExtractFeatures(raster, map.resolution(), options.features).corners;
  library->window = std::make_shared<const MatchWindow>(MakeMatchWindow(raster, options.tolerance_cells));
  library->map = std::move(map);
  return library;
}

}  // namespace pslam
