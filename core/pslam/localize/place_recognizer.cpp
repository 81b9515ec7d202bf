#include "pslam/localize/place_recognizer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pslam/graph/thinned_cloud.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {
namespace {

// A scan joins the cloud only after the robot moved this much since the last one that did: a
// robot standing still adds nothing new, and the cloud stays bounded.
constexpr double kMinStep = 0.1;       // m
constexpr double kMinTurn = 0.1;       // rad
constexpr std::size_t kMaxScans = 400;

double AngleBetween(double a, double b) { return std::abs(NormalizeAngle(a - b)); }

// The map at a coarser resolution: each cell the most occupied of the known cells it covers. The
// search over a whole building at every heading costs with the cube of the inverse resolution.
OccupancyGrid Coarsen(const OccupancyGrid& map, double resolution) {
  const int factor = std::max(1, static_cast<int>(std::lround(resolution / map.resolution())));
  if (factor == 1) return map;
  OccupancyGrid coarse(map.resolution() * factor);
  const CellBox box = map.KnownBounds();
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      const OccupancyGrid::Cell c = map.At(x, y);
      if (c == OccupancyGrid::kUnknown) continue;
      // Floor division: cell indices are negative below the origin.
      const auto down = [factor](int v) { return v >= 0 ? v / factor : -((-v + factor - 1) / factor); };
      OccupancyGrid::Cell& out = coarse.MutableAt(down(x), down(y));
      out = out == OccupancyGrid::kUnknown ? c : std::max(out, c);
    }
  }
  return coarse;
}

}  // namespace

PlaceRecognizer::PlaceRecognizer(const OccupancyGrid& map, const PlaceRecognitionOptions& options)
    : options_(options), stack_(Coarsen(map, options.search_resolution), options.search_depth) {
  const CellBox box = map.KnownBounds();
  const double res = map.resolution();
  const Eigen::Vector2d low = box.min.cast<double>() * res, high = (box.max.cast<double>() + Eigen::Vector2d::Ones()) * res;
  guess_ = Pose2D((low.x() + high.x()) / 2.0, (low.y() + high.y()) / 2.0, 0.0);
  window_ = (high - low).maxCoeff() / 2.0 + res;
}

void PlaceRecognizer::Reset() {
  scans_.clear();
  travelled_ = 0.0;
  searched_at_ = -1.0;
}

void PlaceRecognizer::Add(const std::vector<Eigen::Vector2f>& hits, const Pose2D& odometry) {
  if (!scans_.empty()) {
    const Pose2D& last = scans_.back().odometry;
    const double step = (odometry.translation() - last.translation()).norm();
    if (step < kMinStep && AngleBetween(odometry.theta, last.theta) < kMinTurn) return;
    travelled_ += step;
  }
  scans_.push_back({odometry, travelled_, hits});
  while (scans_.size() > kMaxScans || (scans_.size() > 1 && travelled_ - scans_.front().travelled > options_.cloud_travel)) {
    scans_.pop_front();
  }
}

bool PlaceRecognizer::SearchDue() const {
  if (scans_.empty()) return false;
  if (searched_at_ < 0.0) return travelled_ >= options_.first_search_after;
  return travelled_ - searched_at_ >= options_.search_every;
}

std::vector<Eigen::Vector2f> PlaceRecognizer::Cloud() const {
  const Pose2D to_newest = scans_.back().odometry.inverse();
  ThinnedCloud thinned_cloud(options_.cloud_spacing);
  // Newest scans first: where the cloud is thinned, the points seen last (least drift) stay.
  for (auto scan = scans_.rbegin(); scan != scans_.rend(); ++scan) {
    const Pose2D relative = to_newest * scan->odometry;
    for (const Eigen::Vector2f& hit : scan->hits) thinned_cloud.Add(relative * hit.cast<double>());
  }
  return SelectEvenly(thinned_cloud.Take(), options_.max_points);
}

PlaceMatch PlaceRecognizer::Search() {
  PlaceMatch out;
  searched_at_ = travelled_;
  if (scans_.empty()) return out;
  std::vector<Eigen::Vector2f> cloud = Cloud();
  out.points = static_cast<int>(cloud.size());
  if (cloud.empty()) return out;
  // The cloud is searched for about its centroid: the search's angular step shrinks with the
  // farthest point's distance from the origin, and the newest scan is at the cloud's edge.
  Eigen::Vector2f centroid = Eigen::Vector2f::Zero();
  for (const Eigen::Vector2f& p : cloud) centroid += p;
  centroid /= static_cast<float>(cloud.size());
  for (Eigen::Vector2f& p : cloud) p -= centroid;
  const Pose2D newest_in_cloud(-centroid.x(), -centroid.y(), 0.0);
  const auto robot = [&](const Pose2D& cloud_pose) { return cloud_pose * newest_in_cloud; };
  // Over the whole map from its centre, at every heading.
  BranchAndBoundOptions search{.linear_window = window_, .angular_window = std::numbers::pi, .min_score = options_.min_score};
  const BranchAndBoundResult best = MatchByBranchAndBound(stack_, cloud, guess_, search);
  if (!best.found) return out;
  out.pose = robot(best.pose);
  out.score = best.score;
  // The best place elsewhere, searched for only above what would make it a rival.
  search.min_score = std::max(options_.min_score, options_.ambiguity_ratio * best.score);
  const auto near_best = [&](const Pose2D& cloud_pose) {
    const Pose2D p = robot(cloud_pose);
    return (p.translation() - out.pose.translation()).norm() < options_.ambiguity_distance &&
           AngleBetween(p.theta, out.pose.theta) < options_.ambiguity_angle;
  };
  const BranchAndBoundResult rival = MatchByBranchAndBound(stack_, cloud, guess_, search, near_best);
  if (rival.found) {
    out.rival = robot(rival.pose);
    out.rival_score = rival.score;
  }
  out.outcome = rival.found ? PlaceMatch::Outcome::kAmbiguous : PlaceMatch::Outcome::kUnique;
  return out;
}

}  // namespace pslam
