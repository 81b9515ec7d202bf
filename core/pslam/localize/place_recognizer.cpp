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
// Turning nearly all the way round in place shows the robot's whole surroundings, which tells a
// place apart as well as metres of travel: a search is due then too.
constexpr double kSearchEveryTurn = 6.0;  // rad

double AngleBetween(double a, double b) { return std::abs(NormalizeAngle(a - b)); }

// The map at a coarser resolution: each cell the most occupied (or the most free) of the known
// cells it covers. The search over a whole building at every heading costs with the cube of the
// inverse resolution.
enum class Pool { kMostOccupied, kMostFree };
OccupancyGrid Coarsen(const OccupancyGrid& map, double resolution, Pool pool) {
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
      out = out == OccupancyGrid::kUnknown ? c : pool == Pool::kMostOccupied ? std::max(out, c) : std::min(out, c);
    }
  }
  return coarse;
}

}  // namespace

PlaceRecognizer::PlaceRecognizer(const OccupancyGrid& map, const PlaceRecognitionOptions& options)
    : options_(options),
      stack_(Coarsen(map, options.search_resolution, Pool::kMostOccupied), options.search_depth),
      floor_(Coarsen(map, options.search_resolution, Pool::kMostFree)) {
  const CellBox box = map.KnownBounds();
  const double res = map.resolution();
  const Eigen::Vector2d low = box.min.cast<double>() * res, high = (box.max.cast<double>() + Eigen::Vector2d::Ones()) * res;
  guess_ = Pose2D((low.x() + high.x()) / 2.0, (low.y() + high.y()) / 2.0, 0.0);
  window_ = (high - low).maxCoeff() / 2.0 + res;
}

void PlaceRecognizer::Reset() {
  scans_.clear();
  travelled_ = 0.0;
  turned_ = 0.0;
  searched_at_ = -1.0;
  searched_turn_ = 0.0;
}

void PlaceRecognizer::Add(const std::vector<Eigen::Vector2f>& hits, const Pose2D& odometry) {
  if (!scans_.empty()) {
    const Pose2D& last = scans_.back().odometry;
    const double step = (odometry.translation() - last.translation()).norm();
    if (step < kMinStep && AngleBetween(odometry.theta, last.theta) < kMinTurn) return;
    travelled_ += step;
    turned_ += AngleBetween(odometry.theta, last.theta);
  }
  scans_.push_back({odometry, travelled_, hits});
  while (scans_.size() > kMaxScans || (scans_.size() > 1 && travelled_ - scans_.front().travelled > options_.cloud_travel)) {
    scans_.pop_front();
  }
}

bool PlaceRecognizer::SearchDue() const {
  if (scans_.empty()) return false;
  if (turned_ - searched_turn_ >= kSearchEveryTurn) return true;
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

bool PlaceRecognizer::StandsFree(const Pose2D& robot) const {
  const Eigen::Vector2i cell = floor_.WorldToCell(robot.translation());
  const OccupancyGrid::Cell c = floor_.At(cell.x(), cell.y());
  return c != OccupancyGrid::kUnknown && CellProbability(c) < kFreeCellProbability;
}

PlaceMatch PlaceRecognizer::Search() {
  PlaceMatch out;
  searched_at_ = travelled_;
  searched_turn_ = turned_;
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
  // Only places where the robot stands in free space: a cloud can also fit the outside of a
  // building, with the robot in its wall.
  const auto off_free = [&](const Pose2D& cloud_pose) { return !StandsFree(robot(cloud_pose)); };
  const BranchAndBoundResult best = MatchByBranchAndBound(stack_, cloud, guess_, search, off_free);
  if (!best.found) return out;
  out.pose = robot(best.pose);
  out.score = best.score;
  // The best place elsewhere, searched for only above what would make it a rival.
  const bool in_place = travelled_ - scans_.front().travelled < options_.in_place_travel;
  const double ambiguity_ratio = in_place ? options_.ambiguity_ratio_in_place : options_.ambiguity_ratio;
  // A rival needs only to come close to the best, even below min_score: a best place just above
  // it is otherwise unique merely because its rivals fell just below.
  search.min_score = ambiguity_ratio * best.score;
  search.first_above_min_score = true;  // any rival makes the place ambiguous
  const auto near_best_or_off_free = [&](const Pose2D& cloud_pose) {
    const Pose2D p = robot(cloud_pose);
    return !StandsFree(p) || ((p.translation() - out.pose.translation()).norm() < options_.ambiguity_distance &&
                              AngleBetween(p.theta, out.pose.theta) < options_.ambiguity_angle);
  };
  const BranchAndBoundResult rival = MatchByBranchAndBound(stack_, cloud, guess_, search, near_best_or_off_free);
  if (rival.found) {
    out.rival = robot(rival.pose);
    out.rival_score = rival.score;
  }
  out.outcome = rival.found ? PlaceMatch::Outcome::kAmbiguous : PlaceMatch::Outcome::kUnique;
  return out;
}

}  // namespace pslam
