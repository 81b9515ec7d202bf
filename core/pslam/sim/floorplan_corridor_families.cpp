// Floor plans of repeated rooms along corridors: office, hotel, hospital ward, school. Each draws
// its dimensions, then as many rooms as bring the outline to the area it aims at.
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "pslam/sim/floorplan_families.hpp"

namespace pslam::floorplan {
namespace {

constexpr double t = Canvas::kWall;
constexpr double kMaxCorridor = 90.0;  // m: longer buildings get a second corridor

// The most rooms (at least n_min) whose outline area stays within 'target'.
int CountForArea(const std::function<double(int)>& area, double target, int n_min) {
  int n = n_min;
  while (area(n + 1) <= target) ++n;
  return n;
}

Pose2D CorridorStart(const Frame& f, double corridor_width) {
  const Vec p = f.Point(1.0, corridor_width / 2.0);
  return Pose2D(p.x(), p.y(), std::atan2(f.axis_u.y(), f.axis_u.x()));
}

}  // namespace

Built BuildOffice(Stream& s) {
  const double target = TargetArea(s);
  const double cw = s.Length(1.6, 2.6), d = s.Length(4.0, 6.5), w = s.Length(3.0, 5.0), door = s.Length(0.9, 1.3);
  const bool two = s.Chance(0.5), loop_wanted = s.Chance(0.5);
  // One corridor would pass kMaxCorridor: two.
  const int corridors = two || (target / (2.0 * d + 2.0 * t + cw) > kMaxCorridor) ? 2 : 1;
  const bool loop = corridors == 2 && loop_wanted;  // a cross corridor at both ends, not only the far one
  const double band = 2.0 * d + 2.0 * t + cw;        // one corridor with its two rows
  const double height = corridors * band + (corridors - 1) * t;
  const double crosses = corridors == 2 ? (loop ? 2.0 : 1.0) : 0.0;
  const auto length = [&](int n) { return n * (w + t) + t; };  // corridor: rooms plus a wall at each end
  const int n = CountForArea([&](int k) { return (length(k) + crosses * cw) * height; }, target, 3);
  const double lc = length(n), x0 = loop ? -cw : 0.0, x1 = corridors == 2 ? lc + cw : lc;
  Canvas canvas({{Vec(x0, 0.0), Vec(x1, height)}});
  Frame first;
  for (int k = 0; k < corridors; ++k) {
    Frame f;
    f.origin = Vec(0.0, k * (band + t) + d + t);
    if (k == 0) first = f;
    DrawWing(canvas, s, f, cw, lc,
             {Row(false, d, RowWidths(s, n, w, 0.1), door, Furnish::kOffice),
              Row(true, d, RowWidths(s, n, w, 0.1), door, Furnish::kOffice)});
  }
  if (corridors == 2) {
    canvas.Carve({Vec(lc, 0.0), Vec(lc + cw, height)});
    canvas.AddPlace(Vec(lc + cw / 2.0, height / 2.0));
    if (loop) canvas.Carve({Vec(-cw, 0.0), Vec(0.0, height)});
  }
  char text[200];
  std::snprintf(text, sizeof text,
                "office: %d corridor(s) %.2f m wide%s, %d rooms %.2f x %.2f m per row, doors %.2f m", corridors, cw,
                loop ? " in a loop" : "", n, w, d, door);
  return Finish(canvas, CorridorStart(first, cw), text);
}

Built BuildHotel(Stream& s) {
  const double target = TargetArea(s);
  const double cw = s.Length(1.5, 2.0), d = s.Length(5.4, 7.0), w = s.Length(3.4, 4.4), door = s.Length(0.9, 1.0);
  const double band = 2.0 * d + 2.0 * t + cw;
  const int extra = s.Int(-2, 2);  // the second wing's rooms, against the first's
  const auto length = [&](int n) { return n * (w + t) + t; };
  const int n = CountForArea([&](int k) { return band * (length(k) + band + length(std::max(3, k + extra))); },
                             target, 5);
  const int nb = std::max(3, n + extra);
  const double la = length(n), lb = length(nb);
  // Wing A along x, the lobby at its end, wing B along y from the lobby.
  Canvas canvas({{Vec(0.0, 0.0), Vec(la, band)}, {Vec(la, 0.0), Vec(la + band, band)},
                 {Vec(la, band), Vec(la + band, band + lb)}});
  Frame a;
  a.origin = Vec(0.0, d + t);
  DrawWing(canvas, s, a, cw, la,
           {Row(false, d, RowWidths(s, n, w, 0.0), door, Furnish::kHotel),
            Row(true, d, RowWidths(s, n, w, 0.0), door, Furnish::kHotel)});
  const Rect lobby{Vec(la, 0.0), Vec(la + band, band)};
  canvas.Carve(lobby);
  canvas.Scatter(s, lobby, 2, 0.8, 2.5, {});
  canvas.AddOpenPlaces(lobby);
  Frame b;
  b.origin = Vec(la + d + t, band);
  b.axis_u = Vec::UnitY();
  b.axis_v = Vec::UnitX();
  DrawWing(canvas, s, b, cw, lb,
           {Row(false, d, RowWidths(s, nb, w, 0.0), door, Furnish::kHotel),
            Row(true, d, RowWidths(s, nb, w, 0.0), door, Furnish::kHotel)});
  char text[200];
  std::snprintf(text, sizeof text,
                "hotel, L-shaped: two wings of %d and %d identical rooms %.2f x %.2f m per side off a %.2f m corridor, "
                "a lobby at the corner, doors %.2f m", n, nb, w, d, cw, door);
  return Finish(canvas, CorridorStart(a, cw), text);
}

Built BuildHospital(Stream& s) {
  const double target = TargetArea(s);
  const double cw = s.Length(2.4, 3.0), d = s.Length(5.5, 7.0), w = s.Length(6.0, 8.0), door = s.Length(1.2, 1.4);
  const double station = s.Length(6.0, 9.0);  // the nurses' station: an open bay on the high side
  const double band = 2.0 * d + 2.0 * t + cw;
  const auto length = [&](int n) { return n * (w + t) + t; };
  // One ward corridor, or two side by side joined at their far end when one would pass kMaxCorridor.
  int n = CountForArea([&](int k) { return band * length(k); }, target, 4);
  const int bands = length(n) > kMaxCorridor ? 2 : 1;
  if (bands == 2) n = CountForArea([&](int k) { return (length(k) + cw) * (2.0 * band + t); }, target, 4);
  const double lc = length(n), height = bands * band + (bands - 1) * t;
  // Wards, now and then a narrow utility room among them.
  const auto widths = [&](int count) {
    std::vector<double> out;
    for (int i = 0; i < count; ++i) out.push_back(s.Chance(0.1) ? 3.0 : w);
    return out;
  };
  Canvas canvas({{Vec(0.0, 0.0), Vec(bands == 2 ? lc + cw : lc, height)}});
  Frame first;
  for (int k = 0; k < bands; ++k) {
    Frame f;
    f.origin = Vec(0.0, k * (band + t) + d + t);
    if (k == 0) first = f;
    // High side: wards up to the station, the station, wards after it.
    RoomRow before = Row(true, d, widths(n / 2), door, Furnish::kWard);
    const double station_u = before.start_u + before.Length() + t;
    RoomRow after = Row(true, d, {}, door, Furnish::kWard);
    after.start_u = station_u + station + t;
    while (after.start_u + after.Length() + w + t <= lc - t + 1e-9) after.widths.push_back(w);
    DrawWing(canvas, s, f, cw, lc, {Row(false, d, widths(n), door, Furnish::kWard), before, after});
    const Rect bay = f.Box(station_u, cw, station_u + station, cw + t + d);
    canvas.Carve(bay);
    canvas.Scatter(s, bay, 1, 1.2, 3.0, {});
    canvas.AddOpenPlaces(bay);
  }
  if (bands == 2) canvas.Carve({Vec(lc, 0.0), Vec(lc + cw, height)});
  char text[200];
  std::snprintf(text, sizeof text,
                "hospital ward: %d corridor(s) %.2f m wide of %.1f m, wards %.2f x %.2f m with beds on both sides, a "
                "%.1f m nurses' station, doors %.2f m", bands, cw, lc, w, d, station, door);
  return Finish(canvas, CorridorStart(first, cw), text);
}

Built BuildSchool(Stream& s) {
  const double target = TargetArea(s);
  const double cw = s.Length(2.4, 3.5), d = s.Length(6.0, 8.0), w = s.Length(7.0, 9.0), door = s.Length(0.9, 1.2);
  const double gym = s.Length(10.0, 16.0);
  const bool both_sides = s.Chance(0.7);
  const double band = both_sides ? 2.0 * d + 2.0 * t + cw : d + t + cw;
  const auto length = [&](int n) { return n * (w + t) + t; };
  const int n = CountForArea([&](int k) { return band * (length(k) + gym); }, target, 3);
  const double lc = length(n);
  Canvas canvas({{Vec(0.0, 0.0), Vec(lc + gym, band)}});
  Frame f;
  f.origin = Vec(0.0, both_sides ? d + t : 0.0);
  std::vector<RoomRow> rows = {Row(true, d, RowWidths(s, n, w, 0.0), door, Furnish::kClassroom, 2)};
  if (both_sides) rows.push_back(Row(false, d, RowWidths(s, n, w, 0.0), door, Furnish::kClassroom, 2));
  DrawWing(canvas, s, f, cw, lc, rows);
  const Rect hall{Vec(lc, 0.0), Vec(lc + gym, band)};  // the gym, open to the corridor's end
  canvas.Carve(hall);
  canvas.AddOpenPlaces(hall);
  char text[200];
  std::snprintf(text, sizeof text,
                "school: %d classrooms %.2f x %.2f m per side%s of a %.2f m corridor, two %.2f m doors each, a %.1f m "
                "gym at its end", n, w, d, both_sides ? " on both sides" : " on one side", cw, door, gym);
  return Finish(canvas, CorridorStart(f, cw), text);
}

}  // namespace pslam::floorplan
