#pragma once
// A session's map in the forms the REST API serves: PNG, map_server PGM + YAML, JSON metadata,
// single tiles, and hypothesis overlays.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/hypothesis.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "service/live_codec.hpp"

namespace pslam::server {

std::string MapPng(const OccupancyGrid& grid);
// map_server files: a binary PGM (P5), and the YAML that names it 'image_name'.
std::string MapPgm(const OccupancyGrid& grid);
std::string MapYaml(const OccupancyGrid& grid, const std::string& image_name);
nlohmann::json MapMetadata(const OccupancyGrid& grid, bool live);
// One tile in the live view's binary form; nullopt if the grid has no such tile.
std::optional<Bytes> MapTile(const OccupancyGrid& grid, int tx, int ty);

// An RGBA PNG of a hypothesis's predicted cells over their bounding box (one pixel per cell, row 0
// at the top): occupied cells red, free cells green, alpha from the prediction's confidence.
struct Overlay {
  std::string png;
  double origin_x = 0.0, origin_y = 0.0;  // world position of the lower-left pixel corner
  int width = 0, height = 0;
};
Overlay HypothesisOverlay(const HypothesisRecord& hypothesis, double resolution);

}  // namespace pslam::server
