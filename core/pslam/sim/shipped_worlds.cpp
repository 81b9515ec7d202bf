#include "pslam/sim/shipped_worlds.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "pslam/sim/world_file.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {

ShippedWorld MakeMazeWorld(const MazeLayout& m) {
  World world = MakeWalledRoom(m.size, m.size, m.wall_thickness, kShippedWorldResolution);
  // As many squares per row as fit with a corridor on both sides of each; the leftover (zero for
  // the paper's 25 m = 4 x 3.5 m + 5 x 2.2 m) is split evenly so the grid of squares is centred.
  const double pitch = m.obstacle_width + m.corridor_width;
  const int count = static_cast<int>(std::floor((m.size - m.corridor_width) / pitch + 1e-9));
  const double used = count * m.obstacle_width + (count + 1) * m.corridor_width;
  const double first = (m.size - used) / 2.0 + m.corridor_width;
  for (int i = 0; i < count; ++i) {
    for (int j = 0; j < count; ++j) {
      const Eigen::Vector2d lo(first + i * pitch, first + j * pitch);
      FillBox(world, lo, lo + Eigen::Vector2d::Constant(m.obstacle_width), WorldCell::kOccupied);
    }
  }
  char description[200];
  std::snprintf(description, sizeof description,
                "square maze %g m x %g m, %d x %d square obstacles %g m wide, corridors %g m wide (paper Fig. 7a)",
                m.size, m.size, count, count, m.obstacle_width, m.corridor_width);
  // The corner intersection of the first two corridors, facing along the bottom corridor.
  const double corner = first - m.corridor_width / 2.0;
  return {"maze", description, std::move(world), Pose2D(corner, corner, 0.0)};
}

std::vector<ShippedWorld> MakeShippedWorlds() {
  std::vector<ShippedWorld> worlds;
  worlds.push_back(MakeMazeWorld());
  worlds.push_back(MakeOfficeWorld());
  worlds.push_back(MakeIrregularWorld());
  worlds.push_back(MakeRepetitiveOfficeWorld());
  return worlds;
}

void WriteShippedWorlds(const std::string& dir) {
  for (const ShippedWorld& w : MakeShippedWorlds()) {
    SaveWorld(w.world, (std::filesystem::path(dir) / w.name).string(), w.start, w.description);
  }
}

}  // namespace pslam
