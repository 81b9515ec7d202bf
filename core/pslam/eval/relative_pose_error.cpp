#include "pslam/eval/relative_pose_error.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace pslam {
namespace {

constexpr double kStampTolerance = 1e-6;  // s; timestamps are written with microseconds

// Finds a trajectory pose by stamp: exact text, then nearest time within kStampTolerance.
class StampIndex {
 public:
  explicit StampIndex(const std::vector<StampedPose>& trajectory) : trajectory_(trajectory) {
    for (std::size_t i = 0; i < trajectory.size(); ++i) {
      by_text_.emplace(trajectory[i].stamp, i);  // emplace keeps the first of repeated stamps
      by_time_.emplace_back(trajectory[i].time, i);
    }
    std::stable_sort(by_time_.begin(), by_time_.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
  }

  const Pose2D* Find(const std::string& stamp) const {
    if (const auto it = by_text_.find(stamp); it != by_text_.end()) return &trajectory_[it->second].pose;
    const auto t = ParseStampSeconds(stamp);
    if (!t) return nullptr;
    const auto lo = std::lower_bound(by_time_.begin(), by_time_.end(), *t - kStampTolerance,
                                     [](const auto& entry, double value) { return entry.first < value; });
    if (lo == by_time_.end() || lo->first > *t + kStampTolerance) return nullptr;
    return &trajectory_[lo->second].pose;
  }

 private:
  const std::vector<StampedPose>& trajectory_;
  std::unordered_map<std::string, std::size_t> by_text_;
  std::vector<std::pair<double, std::size_t>> by_time_;
};

struct MeanStd {
  double mean = 0.0, std = 0.0, max = 0.0;
};

MeanStd Summarize(const std::vector<double>& values) {
  MeanStd s;
  if (values.empty()) return s;
  for (double v : values) s.mean += v;
  s.mean /= static_cast<double>(values.size());
  double var = 0.0;  // two passes: no cancellation for small spreads around a large mean
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / static_cast<double>(values.size()));
  s.max = *std::max_element(values.begin(), values.end());
  return s;
}

}  // namespace

std::vector<Relation> ReadRelations(std::istream& in, const std::string& name) {
  std::vector<Relation> relations;
  ReadNumericRecords(in, name, 8, "t1 t2 x y z roll pitch yaw",
                     [&relations](const std::vector<std::string>& text, const std::vector<double>& v) {
                       relations.push_back({text[0], text[1], Pose2D(v[2], v[3], v[7])});
                     });
  return relations;
}

std::vector<Relation> ReadRelations(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open relations file " + path);
  return ReadRelations(in, path);
}

RpeResult ComputeRpe(const std::vector<StampedPose>& trajectory, const std::vector<Relation>& relations) {
  const StampIndex index(trajectory);
  std::vector<double> trans, rot_deg, trans2, rot2_deg2;
  RpeResult result;
  for (const Relation& relation : relations) {
    const Pose2D* from = index.Find(relation.stamp1);
    const Pose2D* to = index.Find(relation.stamp2);
    if (!from || !to) {
      ++result.missing;
      continue;
    }
    const Pose2D error = Between(relation.delta, Between(*from, *to));
    const double t = std::hypot(error.x, error.y);
    const double r = std::abs(NormalizeAngle(error.theta)) * 180.0 / std::numbers::pi;
    trans.push_back(t);
    rot_deg.push_back(r);
    trans2.push_back(t * t);
    rot2_deg2.push_back(r * r);
  }
  result.used = trans.size();
  const MeanStd t = Summarize(trans), r = Summarize(rot_deg), t2 = Summarize(trans2), r2 = Summarize(rot2_deg2);
  result.trans_mean = t.mean, result.trans_std = t.std, result.trans_max = t.max;
  result.rot_mean_deg = r.mean, result.rot_std_deg = r.std, result.rot_max_deg = r.max;
  result.trans2_mean = t2.mean, result.trans2_std = t2.std;
  result.rot2_mean_deg2 = r2.mean, result.rot2_std_deg2 = r2.std;
  return result;
}

}  // namespace pslam
