#include "pslam/predict/features.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "pslam/common/pose2d.hpp"

namespace pslam {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

cv::Mat OccupiedImage(const CellRaster& raster) {
  cv::Mat image(raster.height, raster.width, CV_8UC1);
  for (int y = 0; y < raster.height; ++y) {
    auto* row = image.ptr<std::uint8_t>(y);
    for (int x = 0; x < raster.width; ++x) row[x] = raster.Local(x, y) == CellState::kOccupied ? 255 : 0;
  }
  return image;
}

double AngleBetween(double a, double b) { return std::abs(NormalizeAngle(a - b)); }

// The line through 'points' by iteratively reweighted least squares with Huber weights (k = 1.345
// cells, as cv::fitLine's DIST_HUBER): a point on it and a unit direction. The first weights come
// from the Hough line (through 'origin' along 'guess'), so that a wall meeting this one at a corner
// starts down-weighted instead of tilting the first fit; each round is then a weighted principal
// axis. On walls sampled as RefineSegment samples them it is as accurate as cv::fitLine, whose
// twenty random restarts took a fifth of a prediction's time.
std::pair<Eigen::Vector2d, Eigen::Vector2d> HuberLineFit(const std::vector<Eigen::Vector2d>& points,
                                                         const Eigen::Vector2d& origin, const Eigen::Vector2d& guess) {
  constexpr double kHuber = 1.345;
  std::vector<double> weights(points.size());
  Eigen::Vector2d centre = origin, direction = guess;
  for (int round = 0; round < 30; ++round) {
    const Eigen::Vector2d normal(-direction.y(), direction.x());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double r = std::abs(normal.dot(points[i] - centre));
      weights[i] = r <= kHuber ? 1.0 : kHuber / r;
    }
    double total = 0.0;
    centre.setZero();
    for (std::size_t i = 0; i < points.size(); ++i) {
      centre += weights[i] * points[i];
      total += weights[i];
    }
    centre /= total;
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d d = points[i] - centre;
      sxx += weights[i] * d.x() * d.x();
      sxy += weights[i] * d.x() * d.y();
      syy += weights[i] * d.y() * d.y();
    }
    const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // the principal axis
    const Eigen::Vector2d next(std::cos(angle), std::sin(angle));
    const bool converged = std::abs(next.x() * direction.y() - next.y() * direction.x()) < 1e-6;
    direction = next;
    if (converged) break;
  }
  return {centre, direction};
}

// Refits the direction of a Hough segment (image coordinates) to the occupied cells within two
// cells of it and projects its end points onto the fitted line. See features.hpp, step 1.
LineSegment RefineSegment(const cv::Mat& occupied, const LineSegment& segment) {
  const Eigen::Vector2d d = segment.b - segment.a;
  const double length = d.norm();
  if (length < 1.0) return segment;
  const Eigen::Vector2d u = d / length, n(-u.y(), u.x());
  std::vector<int> keys;
  for (double t = 0.0; t <= length; t += 0.5) {
    for (int k = -4; k <= 4; ++k) {
      const Eigen::Vector2d p = segment.a + t * u + 0.5 * k * n;
      const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
      if (x < 0 || y < 0 || x >= occupied.cols || y >= occupied.rows) continue;
      if (occupied.at<std::uint8_t>(y, x)) keys.push_back(y * occupied.cols + x);
    }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  if (keys.size() < 3) return segment;
  std::vector<Eigen::Vector2d> points;
  points.reserve(keys.size());
  for (const int key : keys) points.emplace_back(key % occupied.cols, key / occupied.cols);
  const auto [p0, fitted] = HuberLineFit(points, 0.5 * (segment.a + segment.b), u);
  const Eigen::Vector2d v = fitted.dot(u) < 0.0 ? Eigen::Vector2d(-fitted) : fitted;
  return {p0 + (segment.a - p0).dot(v) * v, p0 + (segment.b - p0).dot(v) * v};
}

std::vector<LineSegment> DetectLines(const cv::Mat& occupied, double resolution, const FeatureOptions& options) {
  const double min_length = options.min_line_length_m / resolution;
  const int votes = std::max(3, static_cast<int>(std::lround(options.hough_vote_fraction * min_length)));
  std::vector<cv::Vec4i> raw;
  // HoughLinesP draws its random point order from a fixed seed, so the result is reproducible.
  cv::HoughLinesP(occupied, raw, 1.0, kDeg, votes, min_length, options.max_line_gap_m / resolution);
  std::vector<LineSegment> lines;
  lines.reserve(raw.size());
  for (const cv::Vec4i& l : raw) lines.push_back(RefineSegment(occupied, {{l[0], l[1]}, {l[2], l[3]}}));
  return lines;
}

struct Arm {
  double angle;
  double length;
  int segment;
};

// Rays of the segments passing near 'corner' (features.hpp, step 3).
std::vector<Arm> ArmsOf(const Eigen::Vector2d& corner, const std::vector<LineSegment>& lines, double radius,
                        double min_arm) {
  std::vector<Arm> arms;
  for (int i = 0; i < static_cast<int>(lines.size()); ++i) {
    const LineSegment& s = lines[static_cast<std::size_t>(i)];
    const double length = s.Length();
    if (length < 1e-9) continue;
    const Eigen::Vector2d u = (s.b - s.a) / length;
    const double t = std::clamp((corner - s.a).dot(u), 0.0, length);
    if ((s.a + t * u - corner).norm() > radius) continue;
    const double forward = s.Angle();
    if (length - t >= min_arm) arms.push_back({forward, length - t, i});
    if (t >= min_arm) arms.push_back({NormalizeAngle(forward + std::numbers::pi), t, i});
  }
  return arms;
}

struct Direction {
  double angle;
  double total_length;
  int segment;  // the longest arm's segment: the line used to place the corner
};

std::vector<Direction> ClusterArms(std::vector<Arm> arms, double merge_angle) {
  std::sort(arms.begin(), arms.end(), [](const Arm& a, const Arm& b) {
    return a.length != b.length ? a.length > b.length : a.angle < b.angle;
  });
  std::vector<Direction> directions;
  for (const Arm& arm : arms) {
    auto it = std::find_if(directions.begin(), directions.end(),
                           [&](const Direction& d) { return AngleBetween(d.angle, arm.angle) < merge_angle; });
    if (it == directions.end()) {
      directions.push_back({arm.angle, arm.length, arm.segment});
    } else {
      it->total_length += arm.length;
    }
  }
  std::stable_sort(directions.begin(), directions.end(),
                   [](const Direction& a, const Direction& b) { return a.total_length > b.total_length; });
  return directions;
}

Eigen::Vector2d ProjectOnto(const LineSegment& line, const Eigen::Vector2d& p) {
  const Eigen::Vector2d u = (line.b - line.a).normalized();
  return line.a + (p - line.a).dot(u) * u;
}

// Intersection of the infinite lines through two segments; nullopt when they are near parallel.
std::optional<Eigen::Vector2d> Intersect(const LineSegment& l1, const LineSegment& l2) {
  const Eigen::Vector2d d1 = l1.b - l1.a, d2 = l2.b - l2.a;
  const double det = d1.x() * d2.y() - d1.y() * d2.x();
  if (std::abs(det) < 1e-9 * d1.norm() * d2.norm()) return std::nullopt;
  const Eigen::Vector2d w = l2.a - l1.a;
  const double s = (w.x() * d2.y() - w.y() * d2.x()) / det;
  return Eigen::Vector2d(l1.a + s * d1);
}

// True when the cells just past a wall end (opposite to its arm at 'angle') include unexplored
// ones: the wall may go on, and its "end" is where exploration stopped, not a feature of the
// building. Such ends would otherwise be the control point nearest to every frontier.
bool EndsInUnknown(const CellRaster& raster, const Eigen::Vector2d& end, double angle) {
  const Eigen::Vector2d u(std::cos(angle), std::sin(angle)), n(-u.y(), u.x());
  for (int k = 1; k <= 3; ++k) {
    for (int side = -1; side <= 1; ++side) {
      const Eigen::Vector2d p = end - k * u + side * n;
      const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
      if (x < 0 || y < 0 || x >= raster.width || y >= raster.height) return true;
      if (raster.Local(x, y) == CellState::kUnknown) return true;
    }
  }
  return false;
}

}  // namespace

MapFeatures ExtractFeatures(const CellRaster& raster, double resolution, const FeatureOptions& options) {
  MapFeatures features;
  if (raster.width < 3 || raster.height < 3) return features;  // no room for a corner
  const cv::Mat occupied = OccupiedImage(raster);
  const std::vector<LineSegment> lines = DetectLines(occupied, resolution, options);

  // Corners on the occupied image average-pooled by 'pool' (features.hpp, step 2).
  const int pool = std::max(1, static_cast<int>(std::floor(options.corner_resolution_m / resolution + 1e-9)));
  cv::Mat pooled = occupied;
  if (pool > 1) {
    // Pad to a multiple of the pooling factor so that every pooled pixel averages a full block.
    // Pooling the 8-bit image (averages rounded to 1/255) spares a full-size float copy.
    cv::copyMakeBorder(occupied, pooled, 0, (pool - occupied.rows % pool) % pool, 0,
                       (pool - occupied.cols % pool) % pool, cv::BORDER_CONSTANT, 0);
    cv::resize(pooled, pooled, cv::Size(pooled.cols / pool, pooled.rows / pool), 0.0, 0.0, cv::INTER_AREA);
  }
  cv::Mat smooth;
  pooled.convertTo(smooth, CV_32F, 1.0 / 255.0);
  const double pooled_resolution = resolution * pool;
  cv::GaussianBlur(smooth, smooth, cv::Size(0, 0), options.blur_sigma_m / pooled_resolution);
  std::vector<cv::Point2f> peaks;
  std::vector<float> quality;
  if (smooth.rows > options.corner_block_size && smooth.cols > options.corner_block_size) {
    cv::goodFeaturesToTrack(smooth, peaks, options.max_corners, options.corner_quality,
                            options.corner_spacing_m / pooled_resolution, cv::noArray(), quality,
                            options.corner_block_size, 3 /* Sobel aperture */, options.use_harris, options.harris_k);
  }

  const double radius = options.arm_search_radius_m / resolution;
  const double min_arm = options.min_arm_length_m / resolution;
  const double merge = options.arm_merge_angle_deg * kDeg;
  const Eigen::Vector2d origin = raster.origin.cast<double>();
  for (std::size_t i = 0; i < peaks.size(); ++i) {
    // The centre of pooled pixel p is at pool * (p + 0.5) - 0.5 in map cells.
    const Eigen::Vector2d peak = pool * (Eigen::Vector2d(peaks[i].x, peaks[i].y) + Eigen::Vector2d(0.5, 0.5)) -
                                 Eigen::Vector2d(0.5, 0.5);
    const std::vector<Direction> directions = ClusterArms(ArmsOf(peak, lines, radius, min_arm), merge);
    if (directions.empty()) continue;  // no wall forms this corner: it cannot give an angle
    Corner corner;
    corner.response = quality.size() == peaks.size() ? quality[i] : 0.0;
    const Direction& first = directions.front();
    corner.phi1 = first.angle;
    // The strongest direction that is neither parallel nor opposite to phi1 (30 degrees apart).
    auto second = std::find_if(directions.begin() + 1, directions.end(), [&](const Direction& d) {
      const double between = AngleBetween(d.angle, first.angle);
      return between > 30.0 * kDeg && between < 150.0 * kDeg;
    });
    const LineSegment& line1 = lines[static_cast<std::size_t>(first.segment)];
    Eigen::Vector2d position = ProjectOnto(line1, peak);
    if (second != directions.end()) {
      corner.arms = 2;
      corner.phi2 = second->angle;
      const auto crossing = Intersect(line1, lines[static_cast<std::size_t>(second->segment)]);
      if (crossing && (*crossing - peak).norm() <= 2.0 * radius) position = *crossing;
    } else {
      corner.arms = 1;
      corner.phi2 = NormalizeAngle(first.angle + std::numbers::pi / 2.0);
      if (EndsInUnknown(raster, position, first.angle)) continue;
    }
    corner.position = position + origin;
    features.corners.push_back(corner);
  }
  std::stable_sort(features.corners.begin(), features.corners.end(), [](const Corner& a, const Corner& b) {
    if (a.response != b.response) return a.response > b.response;
    if (a.position.y() != b.position.y()) return a.position.y() < b.position.y();
    return a.position.x() < b.position.x();
  });
  features.lines.reserve(lines.size());
  for (const LineSegment& l : lines) features.lines.push_back({l.a + origin, l.b + origin});
  return features;
}

}  // namespace pslam
