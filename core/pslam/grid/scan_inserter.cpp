#include "pslam/grid/scan_inserter.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pslam/grid/ray_caster.hpp"

namespace pslam {
namespace {
int MilliLogOdds(double p) { return static_cast<int>(std::lround(std::log(p / (1.0 - p)) / OccupancyGrid::kLogOddsPerUnit)); }

// Neighbouring hits further apart than this lie on different surfaces (a door's edge and the room
// behind it): they say nothing about the angle at which a beam meets its surface.
constexpr float kSameSurface = 1.5f;
constexpr float kMaxGrazingStop = 0.5f;  // metres

// How far before hit i its beam stops clearing cells. A beam that meets a wall at a shallow angle
// runs through the wall's own row of cells for cell / sin(angle) before its endpoint; a pose off by
// a centimetre puts the endpoint one row deeper, and the beam would clear a stretch of the wall
// that other beams mark occupied. Those alternating stretches along a wall are structure that is
// not there, and in a corridor longer than the laser's range they pull scan matching along it.
// So the beam stops that far short of its endpoint, less the one cell it never clears anyway.
// `beam` runs from the sensor to hit i, `range` is its length.
float GrazingStop(const std::vector<Eigen::Vector2f>& hits, std::size_t i, const Eigen::Vector2f& beam, float range,
                  float cell) {
  const Eigen::Vector2f& p = hits[i];
  const bool before = i > 0 && (hits[i - 1] - p).norm() < kSameSurface;
  const bool after = i + 1 < hits.size() && (hits[i + 1] - p).norm() < kSameSurface;
  if (!before && !after) return 0.0f;
  const Eigen::Vector2f surface = (after ? hits[i + 1] : p) - (before ? hits[i - 1] : p);
  const float norms = surface.norm() * range;
  if (norms <= 0.0f) return 0.0f;
  const float sine = std::abs(surface.x() * beam.y() - surface.y() * beam.x()) / norms;
  return std::min(kMaxGrazingStop, cell * (1.0f / std::max(sine, 1e-3f) - 1.0f));
}
}  // namespace

ScanInserter::ScanInserter(const ScanInsertOptions& o)
    : hit_(MilliLogOdds(o.hit_probability)),
      miss_(MilliLogOdds(o.miss_probability)),
      lo_(MilliLogOdds(o.min_probability)),
      hi_(MilliLogOdds(o.max_probability)),
      grazing_stop_(o.grazing_stop) {}

void ScanInserter::Insert(const ScanPoints& points, const Pose2D& pose, OccupancyGrid& grid,
                          OccupancyGrid* forget) const {
  const Eigen::Vector2i origin = grid.WorldToCell(pose * points.origin.cast<double>());
  auto miss = [&](int x, int y) {
    grid.AddLogOdds(x, y, miss_, lo_, hi_);
    if (forget) forget->Forget(x, y);
  };
  for (const auto& p : points.free_ends) {
    const Eigen::Vector2i end = grid.WorldToCell(pose * p.cast<double>());
    TraceRay(origin, end, miss);
    miss(end.x(), end.y());
  }
  const float cell = static_cast<float>(grid.resolution());
  for (std::size_t i = 0; i < points.hits.size(); ++i) {
    const Eigen::Vector2f& p = points.hits[i];
    const Eigen::Vector2f beam = p - points.origin;
    const float range = beam.norm();
    if (range <= 0.0f) continue;
    const float stop = grazing_stop_ ? std::min(GrazingStop(points.hits, i, beam, range, cell), range) : 0.0f;
    TraceRay(origin, grid.WorldToCell(pose * (p - beam * (stop / range)).cast<double>()), miss);
  }
  const double per_cell = 1.0 / grid.resolution();
  for (const auto& p : points.hits) {
    const Eigen::Vector2d world = pose * p.cast<double>();
    const Eigen::Vector2i end = grid.WorldToCell(world);
    const Eigen::Vector2f in_cell = (world * per_cell - end.cast<double>()).cast<float>() - Eigen::Vector2f::Constant(0.5f);
    grid.AddHit(end.x(), end.y(), in_cell, hit_, lo_, hi_);
    if (forget) forget->Forget(end.x(), end.y());
  }
}

}  // namespace pslam
