#include "pslam/grid/grid_transform.hpp"

namespace pslam {

OccupancyGrid TransformGrid(const OccupancyGrid& grid, const Pose2D& move) {
  OccupancyGrid out(grid.resolution(), grid.limits());
  const CellBox box = grid.KnownBounds();
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      const OccupancyGrid::Cell c = grid.At(x, y);
      if (c == OccupancyGrid::kUnknown) continue;
      const Eigen::Vector2i to = out.WorldToCell(move * grid.CellCenter({x, y}));
      out.MutableAt(to.x(), to.y()) = c;
    }
  }
  return out;
}

}  // namespace pslam
