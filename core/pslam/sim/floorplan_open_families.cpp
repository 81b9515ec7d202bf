// Floor plans of blocks and halls: the maze (repeated blocks), and the families without repeated
// rooms: the irregular hall, the open-plan floor, and the mixed one (an office wing ending in a hall).
#include <cmath>
#include <cstdio>
#include <numbers>

#include "pslam/sim/floorplan_families.hpp"
#include "pslam/sim/shipped_worlds.hpp"

namespace pslam::floorplan {
namespace {

constexpr double t = Canvas::kWall;

// Meeting rooms along the hall's bottom and top walls from x0 on, furniture and a few partitions
// elsewhere; 'keep_out' (the start, corridor mouths) stays empty.
void FurnishHall(Canvas& canvas, Stream& s, const Rect& hall, double x0, int rooms, std::vector<Rect> keep_out) {
  double x = hall.min.x() + x0;
  for (int i = 0; i < rooms; ++i) {
    const double rw = s.Length(3.0, 6.0), rd = s.Length(3.0, 5.0), door = s.Length(0.9, 1.4);
    if (x + rw + t > hall.max.x() - 2.0 || rd + t > hall.Height() / 2.0 - 2.0) break;
    const bool bottom = s.Chance(0.5);
    const double y0 = bottom ? hall.min.y() : hall.max.y() - rd;
    const Rect room{Vec(x, y0), Vec(x + rw, y0 + rd)};
    canvas.Solid(room.Grown(t));
    canvas.Carve(room);
    const double door_x = x + s.Length(0.4, rw - door - 0.4);
    const double wall_y = bottom ? room.max.y() : room.min.y() - t;
    canvas.Carve({Vec(door_x, wall_y), Vec(door_x + door, wall_y + t)});
    canvas.AddPlace(Vec(door_x + door / 2.0, bottom ? room.max.y() - 0.45 : room.min.y() + 0.45));
    canvas.Scatter(s, room, 1, 0.8, 1.6, {});
    keep_out.push_back(room.Grown(t + kFloorPlanGap));
    x += rw + s.Length(2.0, 6.0);
  }
  const Rect allowed = hall.Grown(-kFloorPlanGap);
  const int partitions = s.Int(1, 3);
  for (int i = 0; i < partitions; ++i) {
    for (int attempt = 0; attempt < 40; ++attempt) {
      const double len = s.Length(2.0, 5.0);
      const bool along_x = s.Chance(0.5);
      const Vec size = along_x ? Vec(len, t) : Vec(t, len);
      const Vec lo(Snap(s.Uniform(allowed.min.x(), allowed.max.x() - size.x())),
                   Snap(s.Uniform(allowed.min.y(), allowed.max.y() - size.y())));
      const Rect r{lo, lo + size};
      bool clear = true;
      for (const Rect& k : keep_out) clear = clear && !k.Overlaps(r);
      if (clear && canvas.TryFurniture(r, allowed)) break;
    }
  }
  canvas.Scatter(s, hall, static_cast<int>(hall.Area() / 30.0), 0.6, 2.4, keep_out);
}

}  // namespace

Built BuildMaze(Stream& s) {
  const double target = TargetArea(s);
  const double block = s.Length(2.5, 4.5), c = s.Length(1.6, 2.6);
  const double pitch = block + c;
  const int ny = s.Int(3, 6);
  const auto side = [&](int k) { return k * pitch + c; };
  int nx = ny;
  while (side(nx + 1) * side(ny) <= target) ++nx;
  while (nx > 3 && side(nx) * side(ny) > target) --nx;
  Canvas canvas({{Vec(0.0, 0.0), Vec(side(nx), side(ny))}});
  canvas.Carve({Vec(0.0, 0.0), Vec(side(nx), side(ny))});
  int missing = 0;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      if ((i + j) > 0 && s.Chance(0.06)) {  // now and then a block is left out: an open square
        ++missing;
        continue;
      }
      // Each block a little off the nominal size, within 10 cm a side.
      const Vec lo(c + i * pitch + s.Length(0.0, 0.1), c + j * pitch + s.Length(0.0, 0.1));
      const Vec hi(c + i * pitch + block - s.Length(0.0, 0.1), c + j * pitch + block - s.Length(0.0, 0.1));
      canvas.Solid({lo, hi});
    }
  }
  canvas.AddOpenPlaces({Vec(0.0, 0.0), Vec(side(nx), side(ny))});
  char text[200];
  std::snprintf(text, sizeof text, "maze: %d x %d blocks %.2f m wide (%d left out), corridors %.2f m", nx, ny, block,
                missing, c);
  return Finish(canvas, Pose2D(c / 2.0, c / 2.0, 0.0), text);
}

Built BuildIrregularHall(Stream& s, std::uint64_t seed) {
  const double area = TargetArea(s);
  IrregularLayout layout;
  layout.size = Snap(std::sqrt(area));
  layout.polygon_count = static_cast<int>(std::lround(16.0 * area / 625.0));
  layout.wall_count = static_cast<int>(std::lround(8.0 * area / 625.0));
  layout.seed = seed;
  ShippedWorld w = MakeIrregularWorld(layout);
  Built built{std::move(w.world), w.start, "hall: " + w.description, layout.size * layout.size, {}};
  built.places.push_back(w.start.translation());
  return built;
}

Built BuildOpenPlan(Stream& s) {
  const double area = TargetArea(s), aspect = s.Uniform(1.0, 2.0);
  const double height = Snap(std::sqrt(area / aspect)), width = Snap(area / height);
  const Rect hall{Vec(0.0, 0.0), Vec(width, height)};
  Canvas canvas({hall});
  canvas.Carve(hall);
  const int rooms = s.Int(2, 4);
  FurnishHall(canvas, s, hall, 5.0, rooms, {{Vec(0.0, 0.0), Vec(3.0, 3.0)}});
  canvas.AddOpenPlaces(hall);
  char text[160];
  std::snprintf(text, sizeof text, "open-plan floor %.1f x %.1f m: meeting rooms, partitions, furniture at random",
                width, height);
  return Finish(canvas, Pose2D(1.2, 1.2, std::numbers::pi / 4.0), text);
}

Built BuildMixed(Stream& s) {
  const double target = TargetArea(s);
  const double cw = s.Length(1.8, 2.4), d = s.Length(4.0, 6.0), w = s.Length(3.0, 4.5), door = s.Length(0.9, 1.2);
  const double band = 2.0 * d + 2.0 * t + cw;
  // The wing takes 40-65 % of the area (its corridor 60 m at most), the hall the rest.
  const double wing_share = s.Uniform(0.4, 0.65), hall_aspect = s.Uniform(0.7, 1.4);
  int n = 3;
  while (((n + 1) * (w + t) + t) * band <= target * wing_share && (n + 1) * (w + t) + t <= 60.0) ++n;
  const double lc = n * (w + t) + t;
  // The hall, centred on the wing, at least as tall as it.
  const double hall_area = std::max(100.0, target - lc * band);
  const double hall_h = Snap(std::max(band, std::sqrt(hall_area * hall_aspect))), hall_w = Snap(hall_area / hall_h);
  const double hall_y = Snap((band - hall_h) / 2.0);
  const Rect hall{Vec(lc, hall_y), Vec(lc + hall_w, hall_y + hall_h)};
  Canvas canvas({{Vec(0.0, 0.0), Vec(lc, band)}, hall});
  Frame f;
  f.origin = Vec(0.0, d + t);
  DrawWing(canvas, s, f, cw, lc,
           {Row(false, d, RowWidths(s, n, w, 0.1), door, Furnish::kOffice),
            Row(true, d, RowWidths(s, n, w, 0.1), door, Furnish::kOffice)});
  canvas.Carve(hall);
  const Rect mouth{Vec(lc, d + t - kFloorPlanGap), Vec(lc + 3.0, d + t + cw + kFloorPlanGap)};
  FurnishHall(canvas, s, hall, 4.0, s.Int(0, 2), {mouth});
  canvas.AddOpenPlaces(hall);
  char text[200];
  std::snprintf(text, sizeof text,
                "mixed: an office wing of %d rooms %.2f x %.2f m per side on a %.2f m corridor, ending in an open hall "
                "%.1f m wide", n, w, d, cw, hall_w);
  return Finish(canvas, Pose2D(1.0, d + t + cw / 2.0, 0.0), text);
}

}  // namespace pslam::floorplan
