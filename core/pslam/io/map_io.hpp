#pragma once
// Occupancy maps in the ROS map_server format: an 8-bit image (PGM or PNG) plus a YAML file with
// resolution and origin. Saved maps open in RViz/nav stacks, and maps from other tools load here.
//
// Trinary semantics, as map_server applies them (occupancy p = (255 - pixel) / 255 unless negated):
//   p > occupied_thresh -> occupied, p < free_thresh -> free, anything else -> unknown.
// We write 0 (occupied), 254 (free) and 205 (unknown; p = 0.196078 is just above free_thresh).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

inline constexpr double kMapOccupiedThreshold = 0.65;
inline constexpr double kMapFreeThreshold = 0.196;
inline constexpr std::uint8_t kMapPixelOccupied = 0;
inline constexpr std::uint8_t kMapPixelFree = 254;
inline constexpr std::uint8_t kMapPixelUnknown = 205;

// Probabilities given to loaded cells. A trinary image carries no confidence, so loaded cells get
// the saturation limits of the default ScanInsertOptions: a loaded map reads like a converged map
// of our own, and saving it again reproduces the same image.
inline constexpr double kLoadedOccupiedProbability = 0.97;
inline constexpr double kLoadedFreeProbability = 0.12;

// A rendered map image. Pixel (col, row) shows cell (cell_min.x + col, cell_min.y + height-1 - row):
// row 0 is the top of the map (highest y), as image viewers and map_server expect.
struct MapImage {
  int width = 0;
  int height = 0;
  double resolution = 0.0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // world position of the lower-left pixel corner
  std::vector<std::uint8_t> pixels;                 // row-major, row 0 = top
};

// Renders the known part of 'grid' (KnownBounds() plus a 1-cell unknown margin) with trinary
// pixels. An empty grid renders as 3x3 unknown pixels around cell (0, 0).
MapImage RenderMapImage(const OccupancyGrid& grid);

// The rendered image as PNG bytes.
std::vector<std::uint8_t> EncodeMapPng(const OccupancyGrid& grid);

// The map_server files of a rendered image, as SaveMap writes them: a binary PGM (P5), and the
// YAML that names its image 'image_file' (resolution written exactly, origin to 10 digits).
std::string MapPgmBytes(const MapImage& image);
std::string MapYamlText(const MapImage& image, const std::string& image_file);

// Writes 'prefix'.pgm (binary P5), 'prefix'.yaml and 'prefix'.png. Throws std::runtime_error naming
// the file when one cannot be written.
void SaveMap(const OccupancyGrid& grid, const std::string& prefix);

// Reads a map_server YAML and its image (PGM P5/P2, or anything OpenCV decodes, e.g. PNG); the image
// path is relative to the YAML's folder. Honours negate, the thresholds and mode (trinary or scale;
// raw is rejected). Cells sit on the world-anchored grid of OccupancyGrid, so the origin is snapped
// to the nearest multiple of the resolution: exact for maps saved by SaveMap, off by at most half a
// cell for maps whose origin is not cell-aligned. Throws std::runtime_error naming the file on any
// bad input (missing or duplicate keys, bad values, unreadable or truncated image).
OccupancyGrid LoadMap(const std::string& yaml_path);

// LoadMap from memory: the YAML's text and the bytes of its image (the YAML's 'image' key must be
// there but names no file here). Errors name 'name' instead of a file.
OccupancyGrid ParseMap(const std::string& yaml_text, const std::string& image_bytes, const std::string& name);

}  // namespace pslam
