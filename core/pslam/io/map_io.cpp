#include "pslam/io/map_io.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace pslam {
namespace {

namespace fs = std::filesystem;

// ---- Rendering and writing -------------------------------------------------------------------

std::uint8_t TrinaryPixel(OccupancyGrid::Cell cell) {
  if (cell == OccupancyGrid::kUnknown) return kMapPixelUnknown;
  const double p = CellProbability(cell);
  if (p > kMapOccupiedThreshold) return kMapPixelOccupied;
  if (p < kMapFreeThreshold) return kMapPixelFree;
  return kMapPixelUnknown;  // uncertain cells are unknown to map_server in trinary mode
}

cv::Mat AsMat(const MapImage& image) {
  // A view, not a copy: OpenCV only reads it.
  return cv::Mat(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.pixels.data()));
}

std::vector<std::uint8_t> EncodePng(const MapImage& image) {
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", AsMat(image), bytes)) throw std::runtime_error("PNG encoding of the map failed");
  return bytes;
}

void WriteFile(const std::string& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("cannot write map file " + path);
}

// Shortest text that reads back as the same double, so the resolution round-trips exactly.
std::string ExactNumber(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace

std::string MapPgmBytes(const MapImage& image) {
  char header[128];
  std::snprintf(header, sizeof header, "P5\n# CREATOR: pslam %.3f m/pix\n%d %d\n255\n", image.resolution, image.width,
                image.height);
  std::string bytes(header);
  bytes.append(image.pixels.begin(), image.pixels.end());
  return bytes;
}

std::string MapYamlText(const MapImage& image, const std::string& image_file) {
  // The origin is a multiple of the resolution (e.g. -0.15000000000000002); 10 significant digits
  // read well and still round to the same cell on load.
  char origin[128];
  std::snprintf(origin, sizeof origin, "[%.10g, %.10g, 0.0]", image.origin.x(), image.origin.y());
  std::ostringstream yaml;
  yaml << "image: " << image_file << "\n"
       << "resolution: " << ExactNumber(image.resolution) << "\n"
       << "origin: " << origin << "\n"
       << "negate: 0\n"
       << "occupied_thresh: " << kMapOccupiedThreshold << "\n"
       << "free_thresh: " << kMapFreeThreshold << "\n"
       << "mode: trinary\n";
  return yaml.str();
}

namespace {

// ---- YAML ------------------------------------------------------------------------------------

enum class MapMode { kTrinary, kScale };

struct MapYaml {
  std::string image;  // as written in the file
  double resolution = 0.0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  bool negate = false;
  double occupied_thresh = kMapOccupiedThreshold;
  double free_thresh = kMapFreeThreshold;
  MapMode mode = MapMode::kTrinary;
};

[[noreturn]] void Fail(const std::string& file, const std::string& what) {
  throw std::runtime_error(file + ": " + what);
}

std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

std::string_view Unquote(std::string_view s) {
  if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front()) return s.substr(1, s.size() - 2);
  return s;
}

std::optional<double> ParseDouble(std::string_view s) {
  s = Trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // from_chars rejects a leading '+'
  double v = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// YAML comments start at a '#' that begins the line or follows whitespace.
std::string_view StripComment(std::string_view line) {
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) return line.substr(0, i);
  }
  return line;
}

// Reads "key: value" lines; keeps only the keys a map YAML has, ignores others, rejects duplicates.
std::map<std::string, std::string> ReadYamlKeys(const std::string& path, std::istream& in) {
  static const char* const kKeys[] = {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode"};
  std::map<std::string, std::string> values;
  std::string raw;
  for (int line_no = 1; std::getline(in, raw); ++line_no) {
    const std::string_view line = Trim(StripComment(raw));
    if (line.empty() || line == "---") continue;
    const auto colon = line.find(':');
    const std::string where = "line " + std::to_string(line_no) + ": ";
    if (colon == std::string_view::npos) Fail(path, where + "expected 'key: value', got '" + std::string(line) + "'");
    const std::string key(Trim(line.substr(0, colon)));
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) continue;
    if (values.count(key)) Fail(path, where + "duplicate key '" + key + "'");
    values[key] = std::string(Unquote(Trim(line.substr(colon + 1))));
  }
  return values;
}

double RequireNumber(const std::string& path, const std::string& key, const std::string& text) {
  const auto v = ParseDouble(text);
  if (!v) Fail(path, "'" + key + "' is not a number: '" + text + "'");
  return *v;
}

Eigen::Vector2d ParseOrigin(const std::string& path, const std::string& text) {
  std::string_view s = Trim(text);
  if (s.size() < 2 || s.front() != '[' || s.back() != ']') Fail(path, "'origin' must be [x, y, yaw], got '" + text + "'");
  s = s.substr(1, s.size() - 2);
  std::vector<double> parts;
  while (true) {
    const auto comma = s.find(',');
    parts.push_back(RequireNumber(path, "origin", std::string(s.substr(0, comma))));
    if (comma == std::string_view::npos) break;
    s.remove_prefix(comma + 1);
  }
  if (parts.size() != 3) Fail(path, "'origin' must have 3 values [x, y, yaw], got '" + text + "'");
  // Our grid is axis-aligned; a rotated map cannot be placed without resampling.
  if (std::abs(parts[2]) > 1e-9) Fail(path, "'origin' yaw must be 0 (rotated maps are not supported), got '" + text + "'");
  return {parts[0], parts[1]};
}

MapYaml ParseMapYaml(const std::string& path, std::istream& in) {
  const auto values = ReadYamlKeys(path, in);
  auto require = [&](const char* key) -> const std::string& {
    const auto it = values.find(key);
    if (it == values.end()) Fail(path, std::string("missing key '") + key + "'");
    return it->second;
  };
  MapYaml yaml;
  yaml.image = require("image");
  if (yaml.image.empty()) Fail(path, "'image' is empty");
  yaml.resolution = RequireNumber(path, "resolution", require("resolution"));
  if (!(yaml.resolution > 0.0)) Fail(path, "'resolution' must be positive, got " + require("resolution"));
  yaml.origin = ParseOrigin(path, require("origin"));
  if (const auto it = values.find("negate"); it != values.end()) {
    if (it->second == "0" || it->second == "false") yaml.negate = false;
    else if (it->second == "1" || it->second == "true") yaml.negate = true;
    else Fail(path, "'negate' must be 0 or 1, got '" + it->second + "'");
  }
  if (const auto it = values.find("occupied_thresh"); it != values.end()) {
    yaml.occupied_thresh = RequireNumber(path, "occupied_thresh", it->second);
  }
  if (const auto it = values.find("free_thresh"); it != values.end()) {
    yaml.free_thresh = RequireNumber(path, "free_thresh", it->second);
  }
  if (!(0.0 <= yaml.free_thresh && yaml.free_thresh <= yaml.occupied_thresh && yaml.occupied_thresh <= 1.0)) {
    Fail(path, "thresholds must satisfy 0 <= free_thresh <= occupied_thresh <= 1");
  }
  if (const auto it = values.find("mode"); it != values.end()) {
    if (it->second == "trinary") yaml.mode = MapMode::kTrinary;
    else if (it->second == "scale") yaml.mode = MapMode::kScale;
    else Fail(path, "unsupported 'mode' '" + it->second + "' (trinary or scale)");
  }
  return yaml;
}

// ---- Images ----------------------------------------------------------------------------------

// Pixel brightness in [0, 1], row 0 = top, and which pixels are fully transparent (PNG alpha).
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<double> brightness;
  std::vector<bool> transparent;  // empty when the image has no alpha channel
};

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail(path, "cannot open map image");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Netpbm header token, skipping whitespace and '#' comments.
std::string PgmToken(const std::string& bytes, std::size_t& pos) {
  while (pos < bytes.size()) {
    if (bytes[pos] == '#') {
      while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
    } else if (std::isspace(static_cast<unsigned char>(bytes[pos]))) {
      ++pos;
    } else {
      break;
    }
  }
  const std::size_t start = pos;
  while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos])) && bytes[pos] != '#') ++pos;
  return bytes.substr(start, pos - start);  // empty at the end of the file
}

int PgmInt(const std::string& path, const std::string& bytes, std::size_t& pos, const char* what, int lo, int hi) {
  const std::string token = PgmToken(bytes, pos);
  if (token.empty()) Fail(path, std::string("truncated PGM: no ") + what);
  int v = 0;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size() || v < lo || v > hi) {
    Fail(path, std::string("bad PGM ") + what + " '" + token + "'");
  }
  return v;
}

GrayImage DecodePgm(const std::string& path, const std::string& bytes) {
  const bool binary = bytes[1] == '5';
  std::size_t pos = 2;
  GrayImage image;
  image.width = PgmInt(path, bytes, pos, "width", 1, 1 << 20);
  image.height = PgmInt(path, bytes, pos, "height", 1, 1 << 20);
  const int maxval = PgmInt(path, bytes, pos, "maxval", 1, 65535);
  const std::size_t count = static_cast<std::size_t>(image.width) * image.height;
  // Every pixel takes at least one byte: check before allocating for a corrupt header.
  if (count > bytes.size() - pos) {
    Fail(path, "size mismatch: header says " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                   " but the file has only " + std::to_string(bytes.size()) + " bytes");
  }
  image.brightness.resize(count);
  if (binary) {
    ++pos;  // exactly one whitespace byte separates the header from the raster
    const std::size_t bytes_per_pixel = maxval > 255 ? 2 : 1;
    if (bytes.size() < pos + count * bytes_per_pixel) {
      Fail(path, "size mismatch: header says " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                     " but the raster is " + std::to_string(bytes.size() - std::min(pos, bytes.size())) + " bytes");
    }
    for (std::size_t i = 0; i < count; ++i) {
      const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + pos + i * bytes_per_pixel);
      const int v = bytes_per_pixel == 2 ? (p[0] << 8) | p[1] : p[0];  // 16-bit PGM is big-endian
      image.brightness[i] = static_cast<double>(v) / maxval;
    }
  } else {
    for (std::size_t i = 0; i < count; ++i) {
      std::size_t probe = pos;
      if (PgmToken(bytes, probe).empty()) {
        Fail(path, "size mismatch: header says " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                       " but the file has " + std::to_string(i) + " pixels");
      }
      image.brightness[i] = static_cast<double>(PgmInt(path, bytes, pos, "pixel", 0, maxval)) / maxval;
    }
  }
  return image;
}

// Anything else (PNG, BMP, ...) through OpenCV. Colour pixels use the mean of their colour
// channels, and alpha marks transparency, as map_server does.
GrayImage DecodeWithOpenCv(const std::string& path, const std::string& bytes) {
  if (bytes.empty()) Fail(path, "map image is empty");
  const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<char*>(bytes.data()));
  cv::Mat mat;
  try {
    mat = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {  // corrupt data can throw instead of returning empty
    Fail(path, std::string("unreadable map image: ") + e.what());
  }
  if (mat.empty()) Fail(path, "unreadable map image (not a PGM and not decodable by OpenCV)");
  if (mat.depth() != CV_8U) Fail(path, "map image must have 8-bit channels");
  const int channels = mat.channels();
  const bool has_alpha = channels == 2 || channels == 4;
  const int colour_channels = has_alpha ? channels - 1 : channels;
  GrayImage image;
  image.width = mat.cols;
  image.height = mat.rows;
  image.brightness.resize(static_cast<std::size_t>(mat.cols) * mat.rows);
  if (has_alpha) image.transparent.resize(image.brightness.size());
  for (int r = 0; r < mat.rows; ++r) {
    const std::uint8_t* row = mat.ptr<std::uint8_t>(r);
    for (int c = 0; c < mat.cols; ++c) {
      const std::uint8_t* px = row + static_cast<std::size_t>(c) * channels;
      int sum = 0;
      for (int k = 0; k < colour_channels; ++k) sum += px[k];
      const std::size_t i = static_cast<std::size_t>(r) * mat.cols + c;
      image.brightness[i] = sum / (255.0 * colour_channels);
      if (has_alpha) image.transparent[i] = px[channels - 1] == 0;
    }
  }
  return image;
}

GrayImage DecodeImage(const std::string& path, const std::string& bytes) {
  if (bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '2')) return DecodePgm(path, bytes);
  return DecodeWithOpenCv(path, bytes);
}

OccupancyGrid::Cell MilliLogOdds(double p) {
  return static_cast<OccupancyGrid::Cell>(std::lround(1000.0 * std::log(p / (1.0 - p))));
}

// map_server's pixel semantics; nullopt for unknown.
std::optional<OccupancyGrid::Cell> CellFromPixel(const MapYaml& yaml, double brightness, bool transparent) {
  const double occupancy = yaml.negate ? brightness : 1.0 - brightness;
  if (occupancy > yaml.occupied_thresh) return MilliLogOdds(kLoadedOccupiedProbability);
  if (occupancy < yaml.free_thresh) return MilliLogOdds(kLoadedFreeProbability);
  if (yaml.mode == MapMode::kTrinary || transparent) return std::nullopt;
  // Scale mode keeps in-between values as probabilities; clamp away from 0/1 (finite log-odds).
  return MilliLogOdds(std::clamp(occupancy, 1e-3, 1.0 - 1e-3));
}

// The grid of a parsed YAML and its decoded image.
OccupancyGrid BuildGrid(const MapYaml& yaml, const GrayImage& image) {
  OccupancyGrid grid(yaml.resolution);
  // Snap the origin to the world-anchored cell lattice (exact for origins that are multiples).
  const Eigen::Vector2i lo(static_cast<int>(std::lround(yaml.origin.x() / yaml.resolution)),
                           static_cast<int>(std::lround(yaml.origin.y() / yaml.resolution)));
  for (int row = 0; row < image.height; ++row) {
    const int cy = lo.y() + image.height - 1 - row;
    for (int col = 0; col < image.width; ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * image.width + col;
      const bool transparent = !image.transparent.empty() && image.transparent[i];
      if (const auto cell = CellFromPixel(yaml, image.brightness[i], transparent)) grid.MutableAt(lo.x() + col, cy) = *cell;
    }
  }
  return grid;
}

}  // namespace

MapImage RenderMapImage(const OccupancyGrid& grid) {
  CellBox box = grid.KnownBounds();
  if (box.empty()) box.Extend({0, 0});
  const Eigen::Vector2i lo = box.min - Eigen::Vector2i::Ones(), hi = box.max + Eigen::Vector2i::Ones();
  MapImage image;
  image.width = hi.x() - lo.x() + 1;
  image.height = hi.y() - lo.y() + 1;
  image.resolution = grid.resolution();
  image.origin = lo.cast<double>() * grid.resolution();
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
  for (int row = 0; row < image.height; ++row) {
    const int cy = hi.y() - row;  // row 0 is the top of the map
    for (int col = 0; col < image.width; ++col) {
      image.pixels[static_cast<std::size_t>(row) * image.width + col] = TrinaryPixel(grid.At(lo.x() + col, cy));
    }
  }
  return image;
}

std::vector<std::uint8_t> EncodeMapPng(const OccupancyGrid& grid) { return EncodePng(RenderMapImage(grid)); }

void SaveMap(const OccupancyGrid& grid, const std::string& prefix) {
  const MapImage image = RenderMapImage(grid);
  const std::vector<std::uint8_t> png = EncodePng(image);
  WriteFile(prefix + ".pgm", MapPgmBytes(image));
  WriteFile(prefix + ".png", std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  WriteFile(prefix + ".yaml", MapYamlText(image, fs::path(prefix).filename().string() + ".pgm"));
}

OccupancyGrid LoadMap(const std::string& yaml_path) {
  std::ifstream in(yaml_path);
  if (!in) Fail(yaml_path, "cannot open map YAML");
  const MapYaml yaml = ParseMapYaml(yaml_path, in);
  fs::path image_path(yaml.image);
  if (image_path.is_relative()) image_path = fs::path(yaml_path).parent_path() / image_path;
  return BuildGrid(yaml, DecodeImage(image_path.string(), ReadBytes(image_path.string())));
}

OccupancyGrid ParseMap(const std::string& yaml_text, const std::string& image_bytes, const std::string& name) {
  std::istringstream in(yaml_text);
  const MapYaml yaml = ParseMapYaml(name + " (YAML)", in);
  return BuildGrid(yaml, DecodeImage(name + " (image)", image_bytes));
}

}  // namespace pslam
