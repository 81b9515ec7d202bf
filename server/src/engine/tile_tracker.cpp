#include "engine/tile_tracker.hpp"

namespace pslam::server {

std::vector<Eigen::Vector2i> TileTracker::Changed(const OccupancyGrid& grid) {
  std::vector<Eigen::Vector2i> changed;
  const Eigen::Vector2i origin = grid.tile_origin();
  for (int iy = 0; iy < grid.tiles_high(); ++iy) {
    for (int ix = 0; ix < grid.tiles_wide(); ++ix) {
      const int tx = origin.x() + ix, ty = origin.y() + iy;
      const OccupancyGrid::Tile* now = grid.TileAt(tx, ty);
      if (!now) continue;
      const OccupancyGrid::Tile* before = first_ ? nullptr : previous_.TileAt(tx, ty);
      if (now != before || (before && now->revision != before->revision)) changed.emplace_back(tx, ty);
    }
  }
  if (!first_) {
    // Tiles that vanished: the best particle changed to one that never saw that area.
    const Eigen::Vector2i old_origin = previous_.tile_origin();
    for (int iy = 0; iy < previous_.tiles_high(); ++iy) {
      for (int ix = 0; ix < previous_.tiles_wide(); ++ix) {
        const int tx = old_origin.x() + ix, ty = old_origin.y() + iy;
        if (previous_.TileAt(tx, ty) && !grid.TileAt(tx, ty)) changed.emplace_back(tx, ty);
      }
    }
  }
  previous_ = grid;
  first_ = false;
  return changed;
}

}  // namespace pslam::server
