#include "pslam/predict/alignment.hpp"

namespace pslam {

CellRaster AlignReference(const OccupancyGrid& map, const CellBox& target_box, const Alignment& alignment,
                          const CellClassifier& classify) {
  CellRaster out(target_box.min, target_box.width(), target_box.height());
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      const Eigen::Vector2d cell = (target_box.min + Eigen::Vector2i(x, y)).cast<double>();
      const Eigen::Vector2i source = NearestCell(alignment.ToReference(cell));
      out.Local(x, y) = classify(map.At(source.x(), source.y()));
    }
  }
  return out;
}

}  // namespace pslam
