#include "pslam/experiment/observable_truth.hpp"

namespace pslam {

OccupancyGrid ObservableTruth(const World& world, const OccupancyGrid& reachable) {
  const CellBox& b = world.bounds();
  World observable(world.resolution(), b, WorldCell::kUnknown);
  for (int y = b.min.y(); y <= b.max.y(); ++y) {
    for (int x = b.min.x(); x <= b.max.x(); ++x) {
      if (!reachable.IsKnown(x, y)) continue;
      observable.Set({x, y}, WorldCell::kFree);
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const Eigen::Vector2i face(x + dx, y + dy);
          if (world.IsOccupied(face)) observable.Set(face, WorldCell::kOccupied);
        }
      }
    }
  }
  return observable.ToGrid();
}

}  // namespace pslam
