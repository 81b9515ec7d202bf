#include "pslam/eval/trajectory_io.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pslam {

std::optional<double> ParseStampSeconds(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);  // from_chars rejects a leading '+'
  double v = 0.0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

void ReadNumericRecords(std::istream& in, const std::string& name, std::size_t count, const char* layout,
                        const std::function<void(const std::vector<std::string>& text,
                                                 const std::vector<double>& values)>& on_record) {
  std::string line;
  std::vector<std::string> text;
  std::vector<double> values;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    std::istringstream fields(line);
    text.clear();
    for (std::string s; fields >> s;) text.push_back(s);
    if (text.empty() || text[0].front() == '#') continue;
    const std::string where = name + ":" + std::to_string(line_no) + ": ";
    if (text.size() != count) {
      throw std::runtime_error(where + "expected '" + layout + "', got " + std::to_string(text.size()) + " fields");
    }
    values.clear();
    for (const std::string& field : text) {
      const auto parsed = ParseStampSeconds(field);
      if (!parsed) throw std::runtime_error(where + "not a number: '" + field + "'");
      values.push_back(*parsed);
    }
    on_record(text, values);
  }
}

void WriteTrajectory(std::ostream& out, const std::vector<StampedPose>& poses) {
  char line[256];
  for (const StampedPose& p : poses) {
    char stamp[64];
    if (p.stamp.empty()) std::snprintf(stamp, sizeof stamp, "%.6f", p.time);
    std::snprintf(line, sizeof line, "%s %.6f %.6f %.6f\n", p.stamp.empty() ? stamp : p.stamp.c_str(), p.pose.x,
                  p.pose.y, p.pose.theta);
    out << line;
  }
}

void WriteTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  std::ofstream out(path, std::ios::trunc);
  WriteTrajectory(out, poses);
  out.close();
  if (!out) throw std::runtime_error("cannot write trajectory file " + path);
}

std::vector<StampedPose> ReadTrajectory(std::istream& in, const std::string& name) {
  std::vector<StampedPose> poses;
  ReadNumericRecords(in, name, 4, "timestamp x y theta",
                     [&poses](const std::vector<std::string>& text, const std::vector<double>& v) {
                       poses.push_back({text[0], v[0], Pose2D(v[1], v[2], v[3])});
                     });
  return poses;
}

std::vector<StampedPose> ReadTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open trajectory file " + path);
  return ReadTrajectory(in, path);
}

}  // namespace pslam
