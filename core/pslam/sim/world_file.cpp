#include "pslam/sim/world_file.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

constexpr std::string_view kStartPrefix = "# start:";

std::string_view Trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

std::optional<double> ParseNumber(std::string_view s) {
  s = Trim(s);
  double v = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

void SaveWorld(const World& world, const std::string& prefix, const Pose2D& start, const std::string& description) {
  SaveMap(world.ToGrid(), prefix);
  std::filesystem::remove(prefix + ".png");
  char start_line[128];
  // 9 significant digits: enough to land in the same 5 cm cell, short enough to read.
  std::snprintf(start_line, sizeof start_line, "# start: %.9g, %.9g, %.9g\n", start.x, start.y, start.theta);
  const std::string yaml = prefix + ".yaml";
  std::ofstream out(yaml, std::ios::app);
  out << "# world: " << description << "\n" << start_line;
  out.close();
  if (!out) throw std::runtime_error("cannot write world file " + yaml);
}

std::optional<Pose2D> ReadStartPose(const std::string& yaml_path) {
  std::ifstream in(yaml_path);
  std::string raw;
  while (std::getline(in, raw)) {
    const std::string_view line = Trim(raw);
    if (line.substr(0, kStartPrefix.size()) != kStartPrefix) continue;
    std::string_view rest = line.substr(kStartPrefix.size());
    std::vector<double> values;
    while (true) {
      const auto comma = rest.find(',');
      const auto v = ParseNumber(rest.substr(0, comma));
      if (!v) return std::nullopt;
      values.push_back(*v);
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
    if (values.size() != 3) return std::nullopt;
    return Pose2D(values[0], values[1], values[2]);
  }
  return std::nullopt;
}

}  // namespace pslam
