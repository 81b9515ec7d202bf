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
    : options_(o), resolution_(map.resolution()) {
  const double cap = o.max_distance;
  miss_ = Score(cap * cap, o);
  const CellBox known = map.KnownBounds();
  if (known.empty()) throw std::invalid_argument("the map is empty");
  const int margin = static_cast<int>(std::ceil(cap / resolution_));
  box_.min = known.min - Eigen::Vector2i::Constant(margin);
  box_.max = known.max + Eigen::Vector2i::Constant(margin);
  const int w = box_.width(), h = box_.height();
  std::vector<bool> occupied(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), false);
  known_.assign(occupied.size(), 0);
  for (int y = known.min.y(); y <= known.max.y(); ++y) {
    for (int x = known.min.x(); x <= known.max.x(); ++x) {
      const OccupancyGrid::Cell c = map.At(x, y);
      if (c == OccupancyGrid::kUnknown) continue;
      known_[Index(x, y)] = 1;
      if (CellProbability(c) < o.occupied_probability) continue;
      occupied[Index(x, y)] = true;
      ++occupied_cells_;
    }
  }
  if (occupied_cells_ == 0) throw std::invalid_argument("the map has no obstacle to localize against");
  occupied_.assign(occupied.begin(), occupied.end());
  table_ = SquaredDistanceTransform(occupied, w, h);
  // With face_distance, the distance to an occupied cell's square rather than to its centre: an
  // occupied cell says that a surface lies somewhere in it, and a beam ends on its face.
  const double inset = o.face_distance ? 0.5 : 0.0;
  for (float& v : table_) {
    const double d = std::max(0.0, std::sqrt(static_cast<double>(v)) - inset) * resolution_;
    v = Score(std::min(d * d, cap * cap), o);
  }
}

bool LikelihoodField::NearObstacle(const Eigen::Vector2i& cell) const {
  // An endpoint near an obstacle already is explained by it. Adding it too would thicken each
  // wall into a band over which the field is flat, and the estimate would wander across it.
  const double radius = options_.fill_clearance / resolution_;
  const int r = static_cast<int>(std::floor(radius));
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const Eigen::Vector2i c = cell + Eigen::Vector2i(dx, dy);
      if (dx * dx + dy * dy > radius * radius || c.x() < box_.min.x() || c.y() < box_.min.y() || c.x() > box_.max.x() ||
          c.y() > box_.max.y()) {
        continue;
      }
      if (occupied_[Index(c.x(), c.y())]) return true;
    }
  }
  return false;
}

std::optional<Eigen::Vector2i> LikelihoodField::TableCell(const Eigen::Vector2d& world) const {
  const double fx = std::floor(world.x() / resolution_), fy = std::floor(world.y() / resolution_);
  // Compared as doubles first: a wild point must not overflow the cell index.
  if (!(fx >= box_.min.x() && fx <= box_.max.x() && fy >= box_.min.y() && fy <= box_.max.y())) return std::nullopt;
  return Eigen::Vector2i(static_cast<int>(fx), static_cast<int>(fy));
}

std::optional<bool> LikelihoodField::ExplainedByMap(const Eigen::Vector2d& world) const {
  const std::optional<Eigen::Vector2i> cell = TableCell(world);
  if (!cell || !known_[Index(cell->x(), cell->y())]) return std::nullopt;
  return NearObstacle(*cell);
}

bool LikelihoodField::BeamBlocked(const Eigen::Vector2d& sensor, const Eigen::Vector2d& endpoint) const {
  const Eigen::Vector2d beam = endpoint - sensor;
  const double length = beam.norm() - options_.fill_clearance;
  if (!(length > 0.0)) return false;
  const Eigen::Vector2d step = beam.normalized() * (0.5 * resolution_);
  const int steps = static_cast<int>(length / (0.5 * resolution_));
  Eigen::Vector2d at = sensor;
  for (int i = 0; i < steps; ++i, at += step) {
    const std::optional<Eigen::Vector2i> cell = TableCell(at);
    if (cell && occupied_[Index(cell->x(), cell->y())]) return true;
  }
  return false;
}

bool LikelihoodField::AddUnmappedObstacle(const Eigen::Vector2d& world) {
  const std::optional<Eigen::Vector2i> found = TableCell(world);
  if (!found) return false;
  const Eigen::Vector2i cell = *found;
  if (known_[Index(cell.x(), cell.y())] || NearObstacle(cell)) return false;
  occupied_[Index(cell.x(), cell.y())] = 1;
  ++added_obstacles_;
  // Scores beyond 4 sigma differ from a miss by under half a percent: the table is updated that far.
  const int reach = static_cast<int>(std::ceil(std::min(options_.max_distance, 4.0 * options_.sigma) / resolution_));
  const double inset = options_.face_distance ? 0.5 : 0.0;
  const double cap = options_.max_distance;
  for (int y = std::max(cell.y() - reach, box_.min.y()); y <= std::min(cell.y() + reach, box_.max.y()); ++y) {
    for (int x = std::max(cell.x() - reach, box_.min.x()); x <= std::min(cell.x() + reach, box_.max.x()); ++x) {
      const double d = std::max(0.0, std::hypot(x - cell.x(), y - cell.y()) - inset) * resolution_;
      float& v = table_[Index(x, y)];
      v = std::max(v, Score(std::min(d * d, cap * cap), options_));
    }
  }
  return true;
}

float LikelihoodField::PointLogLikelihood(const Eigen::Vector2d& world) const {
  const std::optional<Eigen::Vector2i> cell = TableCell(world);
  return cell ? table_[Index(cell->x(), cell->y())] : miss_;
}

template <typename T>
double LikelihoodField::Interpolate(const std::vector<T>& table, const Eigen::Vector2d& world, double outside) const {
  // Cell (i, j)'s value holds at its centre ((i + 0.5) r, (j + 0.5) r).
  const double u = world.x() / resolution_ - 0.5, v = world.y() / resolution_ - 0.5;
  const double fu = std::floor(u), fv = std::floor(v);
  if (!(fu >= box_.min.x() && fu < box_.max.x() && fv >= box_.min.y() && fv < box_.max.y())) return outside;
  const auto x = static_cast<std::size_t>(static_cast<int>(fu) - box_.min.x());
  const auto y = static_cast<std::size_t>(static_cast<int>(fv) - box_.min.y());
  const auto w = static_cast<std::size_t>(box_.width());
  const double a = u - fu, b = v - fv;
  const T* row = &table[y * w + x];
  return (1.0 - b) * ((1.0 - a) * row[0] + a * row[1]) + b * ((1.0 - a) * row[w] + a * row[w + 1]);
}

double LikelihoodField::InterpolatedLogLikelihood(const Eigen::Vector2d& world) const {
  return Interpolate(table_, world, miss_);
}

double LikelihoodField::SeenLogLikelihood(const Eigen::Vector2d& world, const Eigen::Vector2d& sensor) const {
  const double here = InterpolatedLogLikelihood(world);
  const Eigen::Vector2d back = sensor - world;
  const double length = back.norm();
  if (length <= resolution_) return here;
  const double blocked = Interpolate(occupied_, world + back * (resolution_ / length), 0.0);
  return here + blocked * (miss_ - here);
}

Pose2D LikelihoodField::Refine(const std::vector<Eigen::Vector2f>& points, const Pose2D& initial, double max_shift,
                               double max_turn, double min_step, const RefinePrior& prior) const {
  const auto score = [&](const Pose2D& pose) {
    const double c = std::cos(pose.theta), s = std::sin(pose.theta);
    const Eigen::Vector2d sensor(pose.x, pose.y);
    double sum = 0.0;
    for (const auto& p : points) {
      sum += SeenLogLikelihood({pose.x + c * p.x() - s * p.y(), pose.y + s * p.x() + c * p.y()}, sensor);
    }
    const Eigen::Vector2d shift(pose.x - initial.x, pose.y - initial.y);
    const double turn = NormalizeAngle(pose.theta - initial.theta);
    return prior.likelihood_weight * sum -
           0.5 * (shift.dot(prior.position_information * shift) + prior.heading_information * turn * turn);
  };
  Pose2D best = initial;
  double best_score = score(best);
  double step_xy = 0.04, step_theta = 0.02;
  for (int evaluations = 0; step_xy >= min_step && evaluations < 200;) {
    bool moved = false;
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {1.0, -1.0}) {
        Pose2D candidate = best;
        if (axis == 0) candidate.x += sign * step_xy;
        else if (axis == 1) candidate.y += sign * step_xy;
        else candidate = Pose2D(best.x, best.y, best.theta + sign * step_theta);
        if (std::hypot(candidate.x - initial.x, candidate.y - initial.y) > max_shift ||
            std::abs(NormalizeAngle(candidate.theta - initial.theta)) > max_turn) {
          continue;
        }
        const double candidate_score = score(candidate);
        ++evaluations;
        if (candidate_score > best_score) {
          best = candidate;
          best_score = candidate_score;
          moved = true;
          break;
        }
      }
    }
    if (!moved) {
      step_xy /= 2.0;
      step_theta /= 2.0;
    }
  }
  return best;
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
