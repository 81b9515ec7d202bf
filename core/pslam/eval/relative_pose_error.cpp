#include "pslam/eval/relative_pose_error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>

namespace pslam {
namespace {

// A stamp's time in seconds. Unix times (~1e9 s) with 6 decimals keep ~1e-7 s in a double, far
// below any tolerance in use. The text wins over StampedPose::time, which in-memory trajectories
// leave at 0.
double StampSeconds(const StampedPose& pose) {
  if (const auto t = ParseStampSeconds(pose.stamp)) return *t;
  return pose.time;
}

// Finds the trajectory pose with the stamp nearest to a given time.
class StampIndex {
 public:
  struct Match {
    const Pose2D* pose;
    double offset_s;  // |query - matched stamp|
  };

  StampIndex(const std::vector<StampedPose>& trajectory, double tolerance_s)
      : trajectory_(trajectory), tolerance_s_(tolerance_s) {
    for (std::size_t i = 0; i < trajectory.size(); ++i) by_time_.emplace_back(StampSeconds(trajectory[i]), i);
    // Stable: of repeated stamps the first in the trajectory comes first.
    std::stable_sort(by_time_.begin(), by_time_.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
  }

  std::optional<Match> Find(const std::string& stamp) const {
    const auto t = ParseStampSeconds(stamp);
    if (!t || by_time_.empty()) return std::nullopt;
    const auto after = FirstAtOrAfter(*t);
    auto nearest = after;
    if (after == by_time_.end() || (after != by_time_.begin() && *t - std::prev(after)->first < after->first - *t)) {
      nearest = FirstAtOrAfter(std::prev(after)->first);  // the first of its repeats
    }
    const double offset = std::abs(nearest->first - *t);
    if (!(offset <= tolerance_s_)) return std::nullopt;
    return Match{&trajectory_[nearest->second].pose, offset};
  }

 private:
  using Entry = std::pair<double, std::size_t>;
  std::vector<Entry>::const_iterator FirstAtOrAfter(double t) const {
    return std::lower_bound(by_time_.begin(), by_time_.end(), t,
                            [](const Entry& entry, double value) { return entry.first < value; });
  }

  const std::vector<StampedPose>& trajectory_;
  double tolerance_s_;
  std::vector<Entry> by_time_;
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

RpeResult ComputeRpe(const std::vector<StampedPose>& trajectory, const std::vector<Relation>& relations,
                     double stamp_tolerance_s) {
  const StampIndex index(trajectory, stamp_tolerance_s);
  std::vector<double> trans, rot_deg, trans2, rot2_deg2;
  RpeResult result;
  result.stamp_tolerance_s = stamp_tolerance_s;
  for (const Relation& relation : relations) {
    const auto from = index.Find(relation.stamp1);
    const auto to = index.Find(relation.stamp2);
    if (!from || !to) {
      ++result.missing;
      continue;
    }
    result.max_stamp_offset_s = std::max({result.max_stamp_offset_s, from->offset_s, to->offset_s});
    const Pose2D error = Between(relation.delta, Between(*from->pose, *to->pose));
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

std::optional<std::string> TooManyMissing(const RpeResult& result, double max_missing_percent) {
  const std::size_t total = result.used + result.missing;
  if (total == 0) return "no relations to evaluate";
  const double percent = 100.0 * static_cast<double>(result.missing) / static_cast<double>(total);
  if (result.used > 0 && percent <= max_missing_percent) return std::nullopt;
  char text[256];
  std::snprintf(text, sizeof text, "%zu of %zu relations (%.1f %%) have a stamp with no trajectory pose within %g s",
                result.missing, total, percent, result.stamp_tolerance_s);
  std::string message = text;
  if (result.used > 0) {
    std::snprintf(text, sizeof text, "; at most %g %% may", max_missing_percent);
    message += text;
  }
  return message;
}

}  // namespace pslam
