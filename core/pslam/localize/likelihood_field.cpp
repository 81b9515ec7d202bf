#include "pslam/localize/likelihood_field.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pslam/explore/distance_transform.hpp"

namespace pslam {
namespace {

float Score(double distance2, const LikelihoodFieldOptions& o) {
  return static_cast<float>(std::log(o.z_hit * std::exp(-distance2 / (2.0 * o.sigma * o.sigma)) + o.z_rand));
}

}  // namespace

LikelihoodField::LikelihoodField(const OccupancyGrid& map, const LikelihoodFieldOptions& o)
    : resolution_(map.resolution()) {
  const double cap = o.max_distance;
  miss_ = Score(cap * cap, o);
  const CellBox known = map.KnownBounds();
  if (known.empty()) throw std::invalid_argument("the map is empty");
  const int margin = static_cast<int>(std::ceil(cap / resolution_));
  box_.min = known.min - Eigen::Vector2i::Constant(margin);
  box_.max = known.max + Eigen::Vector2i::Constant(margin);
  const int w = box_.width(), h = box_.height();
  std::vector<bool> occupied(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), false);
  for (int y = known.min.y(); y <= known.max.y(); ++y) {
    for (int x = known.min.x(); x <= known.max.x(); ++x) {
      const OccupancyGrid::Cell c = map.At(x, y);
      if (c == OccupancyGrid::kUnknown || CellProbability(c) < o.occupied_probability) continue;
      occupied[static_cast<std::size_t>(y - box_.min.y()) * w + (x - box_.min.x())] = true;
      ++occupied_cells_;
    }
  }
  if (occupied_cells_ == 0) throw std::invalid_argument("the map has no obstacle to localize against");
  table_ = SquaredDistanceTransform(occupied, w, h);
  const double cell2 = resolution_ * resolution_;
  for (float& v : table_) v = Score(std::min(static_cast<double>(v) * cell2, cap * cap), o);
}

float LikelihoodField::PointLogLikelihood(const Eigen::Vector2d& world) const {
  const double fx = std::floor(world.x() / resolution_), fy = std::floor(world.y() / resolution_);
  // Compare as doubles first: a wild pose must not overflow the cell index.
  if (!(fx >= box_.min.x() && fx <= box_.max.x() && fy >= box_.min.y() && fy <= box_.max.y())) return miss_;
  const auto x = static_cast<std::size_t>(static_cast<int>(fx) - box_.min.x());
  const auto y = static_cast<std::size_t>(static_cast<int>(fy) - box_.min.y());
  return table_[y * static_cast<std::size_t>(box_.width()) + x];
}

double LikelihoodField::LogLikelihood(const std::vector<Eigen::Vector2f>& points, const Pose2D& pose) const {
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  double sum = 0.0;
  for (const auto& p : points) {
    sum += PointLogLikelihood({pose.x + c * p.x() - s * p.y(), pose.y + s * p.x() + c * p.y()});
  }
  return sum;
}

}  // namespace pslam
