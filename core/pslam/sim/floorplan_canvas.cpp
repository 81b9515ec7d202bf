#include "pslam/sim/floorplan_canvas.hpp"

#include <algorithm>
#include <cmath>

#include "pslam/common/random.hpp"
#include "pslam/sim/shipped_worlds.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam::floorplan {

Stream::Stream(std::uint64_t seed) : state_(SplitMix64(seed ^ 0x5eedf100f0a1ull)) {}

double Stream::Uniform(double lo, double hi) {
  state_ = SplitMix64(state_);
  return lo + (hi - lo) * static_cast<double>(state_ >> 11) * 0x1p-53;
}

int Stream::Int(int lo, int hi) { return std::min(hi, lo + static_cast<int>(Uniform(0.0, hi - lo + 1))); }
bool Stream::Chance(double p) { return Uniform(0.0, 1.0) < p; }
double Stream::Length(double lo, double hi) { return std::clamp(Snap(Uniform(lo, hi)), Snap(lo), Snap(hi)); }

double Snap(double v) { return std::round(v / kShippedWorldResolution) * kShippedWorldResolution; }

Rect Frame::Box(double u0, double v0, double u1, double v1) const {
  const Vec a = Point(u0, v0), b = Point(u1, v1);
  return {a.cwiseMin(b), a.cwiseMax(b)};
}

namespace {

World BlankWorld(const std::vector<Rect>& outline) {
  Rect box = outline.front();
  for (const Rect& r : outline) box = {box.min.cwiseMin(r.min), box.max.cwiseMax(r.max)};
  box = box.Grown(Canvas::kOuterWall);
  const double res = kShippedWorldResolution;
  CellBox cells;
  cells.min = {static_cast<int>(std::floor(box.min.x() / res)) - 1, static_cast<int>(std::floor(box.min.y() / res)) - 1};
  cells.max = {static_cast<int>(std::ceil(box.max.x() / res)) + 1, static_cast<int>(std::ceil(box.max.y() / res)) + 1};
  return World(res, cells, WorldCell::kUnknown);
}

}  // namespace

Canvas::Canvas(const std::vector<Rect>& outline) : world_(BlankWorld(outline)) {
  for (const Rect& r : outline) {
    Solid(r.Grown(kOuterWall));
    outline_area_ += r.Area();
  }
}

void Canvas::Fill(const Rect& r, WorldCell value) { FillBox(world_, r.min, r.max, value); }

void Canvas::AddOpenPlaces(const Rect& area) {
  for (double y = area.min.y() + 1.0; y < area.max.y(); y += 2.0) {
    for (double x = area.min.x() + 1.0; x < area.max.x(); x += 2.0) {
      if (world_.IsDiscFree(Vec(x, y), 0.45)) places_.push_back(Vec(x, y));
    }
  }
}

void Canvas::Furniture(const Rect& r) {
  Solid(r);
  furniture_.push_back(r);
}

bool Canvas::Fits(const Rect& r, const Rect& allowed) const {
  if (!r.Inside(allowed)) return false;
  return std::none_of(furniture_.begin(), furniture_.end(),
                      [&](const Rect& f) { return f.Grown(kFloorPlanGap).Overlaps(r); });
}

bool Canvas::TryFurniture(const Rect& r, const Rect& allowed) {
  if (!Fits(r, allowed)) return false;
  Furniture(r);
  return true;
}

void Canvas::Scatter(Stream& s, const Rect& area, int count, double min_side, double max_side,
                     const std::vector<Rect>& keep_out) {
  const Rect allowed = area.Grown(-kFloorPlanGap);
  for (int i = 0; i < count; ++i) {
    for (int attempt = 0; attempt < 60; ++attempt) {
      const Vec size(s.Length(min_side, max_side), s.Length(min_side, max_side));
      const Vec lo(Snap(s.Uniform(allowed.min.x(), allowed.max.x() - size.x())),
                   Snap(s.Uniform(allowed.min.y(), allowed.max.y() - size.y())));
      const Rect r{lo, lo + size};
      const bool clear = std::none_of(keep_out.begin(), keep_out.end(), [&](const Rect& k) { return k.Overlaps(r); });
      if (clear && TryFurniture(r, allowed)) break;
    }
  }
}

double RoomRow::Length() const {
  double length = 0.0;
  for (const double w : widths) length += w;
  return length + Canvas::kWall * std::max<double>(0.0, static_cast<double>(widths.size()) - 1.0);
}

RoomRow Row(bool high_side, double depth, std::vector<double> widths, double door_width, Furnish furnish,
            int doors_per_room) {
  RoomRow row;
  row.high_side = high_side;
  row.depth = depth;
  row.widths = std::move(widths);
  row.door_width = door_width;
  row.furnish = furnish;
  row.doors_per_room = doors_per_room;
  return row;
}

std::vector<double> RowWidths(Stream& s, int count, double base, double doubles) {
  std::vector<double> widths;
  for (int i = 0; i < count; ++i) {
    if (i + 1 < count && s.Chance(doubles)) {
      widths.push_back(2.0 * base + Canvas::kWall);
      ++i;
    } else {
      widths.push_back(base);
    }
  }
  return widths;
}

namespace {

constexpr double kGap = kFloorPlanGap;

// std::clamp, but lo wins when the range is empty (TryFurniture then refuses what does not fit).
double ClampLow(double v, double lo, double hi) { return std::max(lo, std::min(v, hi)); }

// One room in its own coordinates: a along the corridor from the room's left wall (mirrored when
// 'flip'), b from the door wall into the room.
struct Room {
  const Frame* frame;
  double u0, w, d, v_door;  // v_door: the wing's v of the door wall's room side
  double dir;               // +1: rooms lie at growing v
  bool flip;
  Rect Box(double a0, double b0, double a1, double b1) const {
    if (flip) {
      std::swap(a0, a1);
      a0 = w - a0;
      a1 = w - a1;
    }
    return frame->Box(u0 + a0, v_door + dir * b0, u0 + a1, v_door + dir * b1);
  }
  Rect Interior() const { return Box(0, 0, w, d); }
  // The interior kGap from its walls, but reaching the back wall: for pieces that stand against it.
  Rect AgainstBack() const { return Box(kGap, kGap, w - kGap, d); }
  Rect FreeStanding() const { return Box(kGap, kGap, w - kGap, d - kGap); }
};

void Door(Canvas& c, const Room& r, double a, double width) {
  c.Carve(r.Box(a, -Canvas::kWall, a + width, 0.0));
  c.AddPlace(r.Box(a + width / 2.0, 0.45, a + width / 2.0, 0.45).min);  // just inside the door
}

void FurnishOffice(Canvas& c, Stream& s, const Room& r) {
  const bool cabinet = s.Chance(0.25);
  double back = r.d - kGap;
  if (cabinet) {
    const double cw = s.Length(0.8, 1.2);
    const double a = Snap(s.Uniform(kGap, std::max(kGap, r.w - kGap - cw)));
    if (c.TryFurniture(r.Box(a, r.d - 0.45, a + cw, r.d), r.AgainstBack())) back -= 0.45 + kGap - 0.0;
  }
  if (s.Chance(0.15)) return;  // an empty office
  const double dw = s.Length(1.2, 1.8), dd = s.Length(0.6, 0.8);
  const double a = Snap(ClampLow(r.w / 2.0 - dw / 2.0 + s.Uniform(-0.3, 0.3), kGap, r.w - kGap - dw));
  const double b1 = Snap(back - s.Uniform(0.0, 0.4));
  c.TryFurniture(r.Box(a, b1 - dd, a + dw, b1), r.FreeStanding());
}

void FurnishHotel(Canvas& c, Stream& s, const Room& r, double bath_w, double bath_d) {
  c.TryFurniture(r.Box(0.0, 0.0, bath_w, bath_d), r.Interior());  // the bathroom, in the corner by the door
  const double bed_w = Snap(std::min(1.8, r.w - 2.0 * kGap));
  const double a = Snap(ClampLow(r.w / 2.0 - bed_w / 2.0 + s.Uniform(-0.2, 0.2), kGap, r.w - kGap - bed_w));
  c.TryFurniture(r.Box(a, r.d - 2.05, a + bed_w, r.d), r.AgainstBack());
  if (s.Chance(0.3)) {  // a desk by the window, in some rooms only
    const double dw = s.Length(0.8, 1.2);
    c.TryFurniture(r.Box(r.w - kGap - dw, bath_d + kGap, r.w - kGap, bath_d + kGap + 0.5), r.FreeStanding());
  }
}

void FurnishWard(Canvas& c, Stream& s, const Room& r) {
  const int beds = std::max(1, static_cast<int>((r.w - kGap) / (1.0 + kGap)));
  const double slack = Snap((r.w - kGap - beds * (1.0 + kGap)) / 2.0);
  for (int i = 0; i < beds; ++i) {
    if (s.Chance(0.1)) continue;  // a bed out
    const double a = kGap + slack + i * (1.0 + kGap);
    c.TryFurniture(r.Box(a, r.d - 2.1, a + 1.0, r.d), r.AgainstBack());
  }
}

void FurnishClassroom(Canvas& c, Stream& s, const Room& r) {
  const double teacher = Snap(r.w / 2.0 - 0.8);
  c.TryFurniture(r.Box(teacher, kGap, teacher + 1.6, kGap + 0.8), r.FreeStanding());
  for (double b = kGap + 0.8 + kGap; b + 0.6 <= r.d - kGap + 1e-9; b += 0.6 + kGap) {
    for (double a = kGap; a + 1.2 <= r.w - kGap + 1e-9; a += 1.2 + kGap) {
      if (!s.Chance(0.08)) c.TryFurniture(r.Box(a, b, a + 1.2, b + 0.6), r.FreeStanding());
    }
  }
}

}  // namespace

void DrawWing(Canvas& canvas, Stream& s, const Frame& frame, double corridor_width, double corridor_length,
              const std::vector<RoomRow>& rows) {
  canvas.Carve(frame.Box(0.0, 0.0, corridor_length, corridor_width));
  canvas.AddPlace(frame.Point(corridor_length / 2.0, corridor_width / 2.0));
  for (const RoomRow& row : rows) {
    const double dir = row.high_side ? 1.0 : -1.0;
    const double v_door = row.high_side ? corridor_width + Canvas::kWall : -Canvas::kWall;
    // The row's own look: which side the door is on, the bathroom's size; rooms differ from it a little.
    const bool row_flip = s.Chance(0.5);
    const double bath_w = s.Length(1.5, 1.9), bath_d = std::min(s.Length(1.8, 2.4), Snap(row.depth - 3.1));
    double u = row.start_u;
    for (const double w : row.widths) {
      const bool flip = s.Chance(0.15) ? !row_flip : row_flip;
      const Room room{&frame, u, w, row.depth, v_door, dir, flip};
      canvas.Carve(room.Interior());
      if (row.furnish == Furnish::kHotel) {
        Door(canvas, room, bath_w + 0.3, row.door_width);
      } else if (row.doors_per_room == 2) {
        Door(canvas, room, 0.5, row.door_width);
        Door(canvas, room, w - 0.5 - row.door_width, row.door_width);
      } else {
        Door(canvas, room, Snap(0.5 + (s.Chance(0.2) ? s.Uniform(0.0, 0.4) : 0.0)), row.door_width);
      }
      switch (row.furnish) {
        case Furnish::kOffice: FurnishOffice(canvas, s, room); break;
        case Furnish::kHotel: FurnishHotel(canvas, s, room, bath_w, bath_d); break;
        case Furnish::kWard: FurnishWard(canvas, s, room); break;
        case Furnish::kClassroom: FurnishClassroom(canvas, s, room); break;
        case Furnish::kNone: break;
      }
      u += w + Canvas::kWall;
    }
  }
}

}  // namespace pslam::floorplan
