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
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string s; fields >> s;) f.push_back(s);
    if (f.empty() || f[0].front() == '#') continue;
    const std::string where = name + ":" + std::to_string(line_no) + ": ";
    if (f.size() != 4) {
      throw std::runtime_error(where + "expected 'timestamp x y theta', got " + std::to_string(f.size()) + " fields");
    }
    double v[4];
    for (int i = 0; i < 4; ++i) {
      const auto parsed = ParseStampSeconds(f[i]);
      if (!parsed) throw std::runtime_error(where + "not a number: '" + f[i] + "'");
      v[i] = *parsed;
    }
    poses.push_back({f[0], v[0], Pose2D(v[1], v[2], v[3])});
  }
  return poses;
}

std::vector<StampedPose> ReadTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open trajectory file " + path);
  return ReadTrajectory(in, path);
}

}  // namespace pslam
