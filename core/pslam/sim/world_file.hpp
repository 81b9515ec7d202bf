#pragma once
// World files: a map_server YAML + PGM pair (written by SaveMap, read by LoadWorld) whose YAML also
// carries comment lines map_server ignores:
//   # world: <one-line description>
//   # start: x, y, theta        (a free start pose, metres and radians)
#include <optional>
#include <string>

#include "pslam/common/pose2d.hpp"
#include "pslam/sim/world.hpp"

namespace pslam {

// Writes 'prefix'.yaml and 'prefix'.pgm (SaveMap's PNG copy is removed: one image per world).
// Throws std::runtime_error naming the file when one cannot be written.
void SaveWorld(const World& world, const std::string& prefix, const Pose2D& start, const std::string& description);

// The pose of the first "# start: x, y, theta" line of a world YAML; nullopt when the file cannot
// be read or has no well-formed start line.
std::optional<Pose2D> ReadStartPose(const std::string& yaml_path);

}  // namespace pslam
