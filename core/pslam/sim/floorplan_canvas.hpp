#pragma once
// Building blocks of the floor-plan generator (floorplan.hpp): a seeded number stream, axis-aligned
// rectangles, a canvas that starts as solid building inside its outline and has rooms, corridors
// and doors carved out of it (walls are what is left between them), and a row of rooms along a
// corridor drawn in a local frame so that wings can run in any axis direction.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "pslam/sim/floorplan.hpp"

namespace pslam::floorplan {

using Vec = Eigen::Vector2d;

// Uniform numbers from SplitMix64 (not <random> distributions, whose output differs between
// standard libraries), so a seed gives the same building everywhere.
class Stream {
 public:
  explicit Stream(std::uint64_t seed);
  double Uniform(double lo, double hi);
  int Int(int lo, int hi);       // inclusive
  bool Chance(double p);
  double Length(double lo, double hi);  // uniform, snapped to the 5 cm lattice

 private:
  std::uint64_t state_;
};

double Snap(double v);  // to the 5 cm cell lattice, so walls and doors have exact sizes

struct Rect {
  Vec min, max;
  double Width() const { return max.x() - min.x(); }
  double Height() const { return max.y() - min.y(); }
  double Area() const { return Width() * Height(); }
  Vec Centre() const { return (min + max) / 2.0; }
  Rect Grown(double d) const { return {min - Vec(d, d), max + Vec(d, d)}; }
  bool Overlaps(const Rect& o) const {
    return min.x() < o.max.x() && o.min.x() < max.x() && min.y() < o.max.y() && o.min.y() < max.y();
  }
  bool Inside(const Rect& o) const {
    return min.x() >= o.min.x() && min.y() >= o.min.y() && max.x() <= o.max.x() && max.y() <= o.max.y();
  }
};

// Maps local (u, v) to the world: origin + u * axis_u + v * axis_v, with axes along +-x or +-y.
struct Frame {
  Vec origin = Vec::Zero();
  Vec axis_u = Vec::UnitX();
  Vec axis_v = Vec::UnitY();
  Vec Point(double u, double v) const { return origin + u * axis_u + v * axis_v; }
  Rect Box(double u0, double v0, double u1, double v1) const;
};

class Canvas {
 public:
  static constexpr double kOuterWall = 0.2;  // m
  static constexpr double kWall = 0.1;       // m, interior walls

  // Solid building inside each outline rectangle (and its outer wall), unknown outside.
  explicit Canvas(const std::vector<Rect>& outline);

  void Carve(const Rect& r) { Fill(r, WorldCell::kFree); }
  void Solid(const Rect& r) { Fill(r, WorldCell::kOccupied); }
  // Furniture: occupied, and remembered so later pieces keep their distance.
  void Furniture(const Rect& r);
  // Furniture only if 'r' lies inside 'allowed' and kFloorPlanGap from all earlier furniture.
  bool Fits(const Rect& r, const Rect& allowed) const;
  bool TryFurniture(const Rect& r, const Rect& allowed);
  // Places up to 'count' boxes of random size in 'area' (already carved) with kFloorPlanGap to the
  // area's edges, to each other, to earlier furniture and to the keep-outs (doors, the start).
  void Scatter(Stream& s, const Rect& area, int count, double min_side, double max_side,
               const std::vector<Rect>& keep_out);

  void AddPlace(const Vec& p) { places_.push_back(p); }
  // Places on a 2 m grid over 'area' where the robot's disc lies in free space (after furnishing):
  // every open spot of a hall must be reachable, not only its middle.
  void AddOpenPlaces(const Rect& area);
  double OutlineArea() const { return outline_area_; }
  World Take() { return std::move(world_); }
  const std::vector<Vec>& places() const { return places_; }

 private:
  void Fill(const Rect& r, WorldCell value);

  World world_;
  double outline_area_ = 0.0;
  std::vector<Rect> furniture_;
  std::vector<Vec> places_;
};

// How the rooms of a row are furnished.
enum class Furnish { kOffice, kHotel, kWard, kClassroom, kNone };

// A row of rooms along one side of a corridor, in a wing's local frame: the corridor is
// v in [0, corridor_width]; a row on the low side spans v in [-kWall - depth, -kWall], on the high
// side [corridor_width + kWall, ... + depth]. Rooms start at u = start_u, kWall apart.
struct RoomRow {
  bool high_side = false;
  double start_u = Canvas::kWall;
  double depth = 5.0;
  std::vector<double> widths;  // along u, one per room
  double door_width = 1.0;
  int doors_per_room = 1;
  Furnish furnish = Furnish::kOffice;
  double Length() const;       // sum of widths and the walls between them
};
RoomRow Row(bool high_side, double depth, std::vector<double> widths, double door_width, Furnish furnish,
            int doors_per_room = 1);

// Carves the corridor u in [0, corridor_length] and the rows, doors into the corridor, furniture
// (with the variation between rooms drawn from 's'); adds a place per room and per corridor.
void DrawWing(Canvas& canvas, Stream& s, const Frame& frame, double corridor_width, double corridor_length,
              const std::vector<RoomRow>& rows);

// Room widths for a row: 'count' rooms of 'base' width, a few of them (probability 'doubles')
// merged into double rooms.
std::vector<double> RowWidths(Stream& s, int count, double base, double doubles);

}  // namespace pslam::floorplan
