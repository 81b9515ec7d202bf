// The irregular control world of shipped_worlds.hpp. Random numbers come from SplitMix64 directly,
// not from <random> distributions, whose output differs between standard libraries: the generator
// should reproduce the committed files on other toolchains (up to libm rounding of sin/cos, which
// could at worst flip a cell whose centre sits exactly on a shape's edge).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <vector>

#include "pslam/common/random.hpp"
#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

using Vec = Eigen::Vector2d;

class UniformStream {
 public:
  explicit UniformStream(std::uint64_t seed) : state_(seed) {}
  double Next(double lo, double hi) {
    state_ = SplitMix64(state_);
    return lo + (hi - lo) * static_cast<double>(state_ >> 11) * 0x1p-53;  // 53 random mantissa bits
  }

 private:
  std::uint64_t state_;
};

// An obstacle's footprint: every point within 'radius' of the segment a-b (a capsule; a disc when
// a = b). Capsules hug walls far more tightly than bounding circles, so long walls still fit.
struct Footprint {
  Vec a, b;
  double radius;
};

double PointSegmentDistance(const Vec& p, const Vec& a, const Vec& b) {
  const Vec ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

double Cross(const Vec& u, const Vec& v) { return u.x() * v.y() - u.y() * v.x(); }

double SegmentDistance(const Footprint& f, const Footprint& g) {
  // Proper crossing: distance 0. Otherwise the closest pair involves an endpoint.
  const double d1 = Cross(f.b - f.a, g.a - f.a), d2 = Cross(f.b - f.a, g.b - f.a);
  const double d3 = Cross(g.b - g.a, f.a - g.a), d4 = Cross(g.b - g.a, f.b - g.a);
  if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0) return 0.0;
  return std::min({PointSegmentDistance(f.a, g.a, g.b), PointSegmentDistance(f.b, g.a, g.b),
                   PointSegmentDistance(g.a, f.a, f.b), PointSegmentDistance(g.b, f.a, f.b)});
}

// A convex polygon inside a circle of 'radius': vertices at jittered, increasing angles on the
// circle (convex), then squashed along a random axis (an affine map keeps it convex).
std::vector<Vec> RandomConvexPolygon(UniformStream& u, const Vec& centre, double radius) {
  const int vertices = 3 + static_cast<int>(u.Next(0.0, 5.0));  // 3 to 7
  const double turn = u.Next(0.0, 2.0 * std::numbers::pi);
  const double squash = u.Next(0.45, 1.0), axis = u.Next(0.0, std::numbers::pi);
  const double ca = std::cos(axis), sa = std::sin(axis);
  std::vector<Vec> polygon;
  for (int i = 0; i < vertices; ++i) {
    const double a = turn + 2.0 * std::numbers::pi * (i + u.Next(-0.3, 0.3)) / vertices;
    const Vec p = radius * Vec(std::cos(a), std::sin(a));
    const double along = ca * p.x() + sa * p.y(), across = -sa * p.x() + ca * p.y();
    polygon.push_back(centre + squash * along * Vec(ca, sa) + across * Vec(-sa, ca));
  }
  return polygon;
}

}  // namespace

ShippedWorld MakeIrregularWorld(const IrregularLayout& layout) {
  World world = MakeWalledRoom(layout.size, layout.size, layout.wall_thickness, kShippedWorldResolution);
  const Pose2D start(2.0, 2.0, std::numbers::pi / 4.0);
  constexpr double kStartClearance = 1.5;  // m kept empty around the start
  constexpr int kAttemptsPerObstacle = 200;

  UniformStream u(layout.seed);
  std::vector<Footprint> placed;
  // Rejection sampling: a footprint (centred at a random point, then shaped by 'make') must keep
  // 'min_gap' from the walls, the start and every other one, so that obstacles never touch and the
  // free space stays connected.
  const auto fits = [&](const Footprint& f) {
    const double margin = layout.min_gap + f.radius;
    for (const Vec& p : {f.a, f.b}) {
      if (p.x() < margin || p.y() < margin || p.x() > layout.size - margin || p.y() > layout.size - margin) return false;
    }
    if (PointSegmentDistance(start.translation(), f.a, f.b) < f.radius + kStartClearance) return false;
    for (const Footprint& g : placed) {
      if (SegmentDistance(f, g) < f.radius + g.radius + layout.min_gap) return false;
    }
    return true;
  };
  const auto place = [&](const auto& make) -> std::optional<Footprint> {
    for (int attempt = 0; attempt < kAttemptsPerObstacle; ++attempt) {
      const Footprint f = make(Vec(u.Next(0.0, layout.size), u.Next(0.0, layout.size)));
      if (fits(f)) {
        placed.push_back(f);
        return f;
      }
    }
    return std::nullopt;
  };

  // Walls first: long shapes are the hardest to fit once the room fills up.
  constexpr double kWallThickness = 0.15;
  int polygons = 0, walls = 0;
  for (int i = 0; i < layout.wall_count; ++i) {
    const auto wall = place([&](const Vec& c) {
      const double length = u.Next(2.5, 7.0), angle = u.Next(0.0, std::numbers::pi);
      const Vec half = length / 2.0 * Vec(std::cos(angle), std::sin(angle));
      return Footprint{c - half, c + half, kWallThickness / 2.0};
    });
    if (wall) {
      FillSegment(world, wall->a, wall->b, kWallThickness, WorldCell::kOccupied);
      ++walls;
    }
  }
  for (int i = 0; i < layout.polygon_count; ++i) {
    const auto disc = place([&](const Vec& c) { return Footprint{c, c, u.Next(0.4, 1.5)}; });
    if (disc) {
      FillPolygon(world, RandomConvexPolygon(u, disc->a, disc->radius), WorldCell::kOccupied);
      ++polygons;
    }
  }

  char description[200];
  std::snprintf(description, sizeof description,
                "irregular room %g m x %g m: %d random convex polygons and %d walls at odd angles, no repeated "
                "structure (seed %llu)",
                layout.size, layout.size, polygons, walls, static_cast<unsigned long long>(layout.seed));
  return {"irregular", description, std::move(world), start};
}

}  // namespace pslam
