#include "service/foxglove_codec.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/base64.hpp"
#include "service/json_views.hpp"

namespace pslam::server {
namespace {

using nlohmann::json;

std::string Dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

// Millimetres and tenths of a milliradian are all a viewer draws; shorter numbers, smaller messages.
double Round(double v, double scale) { return std::isfinite(v) ? std::round(v * scale) / scale : 0.0; }
double Metres(double v) { return Round(v, 1e3); }
double Unit(double v) { return Round(v, 1e4); }

// JSON Schema pieces of Foxglove's well-known types (field names and types as foxglove/schemas
// defines them).
json Number() { return {{"type", "number"}}; }
json Integer() { return {{"type", "integer"}}; }
json Object(const char* title, json properties) {
  json j = {{"type", "object"}, {"properties", std::move(properties)}};
  if (title) j["title"] = title;
  return j;
}
json ArrayOf(json items) { return {{"type", "array"}, {"items", std::move(items)}}; }
json TimeSchema() { return Object("time", {{"sec", Integer()}, {"nsec", Integer()}}); }
json Vector3Schema() { return Object("foxglove.Vector3", {{"x", Number()}, {"y", Number()}, {"z", Number()}}); }
json QuaternionSchema() {
  return Object("foxglove.Quaternion", {{"x", Number()}, {"y", Number()}, {"z", Number()}, {"w", Number()}});
}
json PoseSchema() { return Object("foxglove.Pose", {{"position", Vector3Schema()}, {"orientation", QuaternionSchema()}}); }
json ColorSchema() { return Object("foxglove.Color", {{"r", Number()}, {"g", Number()}, {"b", Number()}, {"a", Number()}}); }
json DurationSchema() { return Object("duration", {{"sec", Integer()}, {"nsec", Integer()}}); }

json GridSchema() {
  json field = Object("foxglove.PackedElementField", {{"name", {{"type", "string"}}}, {"offset", Integer()},
                                                      {"type", Integer()}});
  return Object("foxglove.Grid", {{"timestamp", TimeSchema()},
                                  {"frame_id", {{"type", "string"}}},
                                  {"pose", PoseSchema()},
                                  {"column_count", Integer()},
                                  {"cell_size", Object("foxglove.Vector2", {{"x", Number()}, {"y", Number()}})},
                                  {"row_stride", Integer()},
                                  {"cell_stride", Integer()},
                                  {"fields", ArrayOf(field)},
                                  {"data", {{"type", "string"}, {"contentEncoding", "base64"}}}});
}

json SceneUpdateSchema() {
  json sphere = Object("foxglove.SpherePrimitive", {{"pose", PoseSchema()}, {"size", Vector3Schema()}, {"color", ColorSchema()}});
  json line = Object("foxglove.LinePrimitive", {{"type", Integer()},
                                                {"pose", PoseSchema()},
                                                {"thickness", Number()},
                                                {"scale_invariant", {{"type", "boolean"}}},
                                                {"points", ArrayOf(Vector3Schema())},
                                                {"color", ColorSchema()},
                                                {"colors", ArrayOf(ColorSchema())},
                                                {"indices", ArrayOf(Integer())}});
  json any_list = ArrayOf({{"type", "object"}});
  json entity = Object("foxglove.SceneEntity", {{"timestamp", TimeSchema()},
                                                {"frame_id", {{"type", "string"}}},
                                                {"id", {{"type", "string"}}},
                                                {"lifetime", DurationSchema()},
                                                {"frame_locked", {{"type", "boolean"}}},
                                                {"metadata", any_list},
                                                {"arrows", any_list},
                                                {"cubes", any_list},
                                                {"spheres", ArrayOf(sphere)},
                                                {"cylinders", any_list},
                                                {"lines", ArrayOf(line)},
                                                {"triangles", any_list},
                                                {"texts", any_list},
                                                {"models", any_list}});
  json deletion = Object("foxglove.SceneEntityDeletion", {{"timestamp", TimeSchema()}, {"type", Integer()},
                                                          {"id", {{"type", "string"}}}});
  return Object("foxglove.SceneUpdate", {{"deletions", ArrayOf(deletion)}, {"entities", ArrayOf(entity)}});
}

json SchemaOf(FoxgloveTopic topic) {
  switch (topic) {
    case FoxgloveTopic::kMap:
    case FoxgloveTopic::kPrediction:
      return GridSchema();
    case FoxgloveTopic::kRobot:
      return Object("foxglove.PoseInFrame", {{"timestamp", TimeSchema()}, {"frame_id", {{"type", "string"}}},
                                             {"pose", PoseSchema()}});
    case FoxgloveTopic::kScan:
      return Object("foxglove.LaserScan", {{"timestamp", TimeSchema()},
                                           {"frame_id", {{"type", "string"}}},
                                           {"pose", PoseSchema()},
                                           {"start_angle", Number()},
                                           {"end_angle", Number()},
                                           {"ranges", ArrayOf(Number())},
                                           {"intensities", ArrayOf(Number())}});
    case FoxgloveTopic::kTrajectory:
    case FoxgloveTopic::kParticles:
      return Object("foxglove.PosesInFrame", {{"timestamp", TimeSchema()}, {"frame_id", {{"type", "string"}}},
                                              {"poses", ArrayOf(PoseSchema())}});
    case FoxgloveTopic::kTransform:
      return Object("foxglove.FrameTransform", {{"timestamp", TimeSchema()},
                                                {"parent_frame_id", {{"type", "string"}}},
                                                {"child_frame_id", {{"type", "string"}}},
                                                {"translation", Vector3Schema()},
                                                {"rotation", QuaternionSchema()}});
    case FoxgloveTopic::kStats:
      // The live view's stats object (schema/ws/live.md): open-ended, its fields may grow.
      return {{"title", "pslam.Stats"}, {"type", "object"}};
    case FoxgloveTopic::kExploration:
      return SceneUpdateSchema();
  }
  return json::object();
}

json Time(std::uint64_t ns) { return {{"sec", ns / 1000000000u}, {"nsec", ns % 1000000000u}}; }
json Vector3(double x, double y) { return {{"x", Metres(x)}, {"y", Metres(y)}, {"z", 0.0}}; }
json Yaw(double theta) { return {{"x", 0.0}, {"y", 0.0}, {"z", Unit(std::sin(theta / 2))}, {"w", Unit(std::cos(theta / 2))}}; }
json PoseJson(double x, double y, double theta) { return {{"position", Vector3(x, y)}, {"orientation", Yaw(theta)}}; }
json Color(double r, double g, double b, double a) { return {{"r", r}, {"g", g}, {"b", b}, {"a", a}}; }

json Sphere(double x, double y, double size, json color) {
  return {{"pose", PoseJson(x, y, 0.0)}, {"size", {{"x", size}, {"y", size}, {"z", size}}}, {"color", std::move(color)}};
}

// The occupancy (percent, 255 unknown) of a block of factor x factor cells: its most occupied
// known cell, so thin walls survive coarsening.
std::uint8_t BlockOccupancy(const OccupancyGrid& grid, int x0, int y0, int factor) {
  int best = -1;
  for (int y = y0; y < y0 + factor; ++y) {
    for (int x = x0; x < x0 + factor; ++x) {
      const OccupancyGrid::Cell c = grid.At(x, y);
      if (c != OccupancyGrid::kUnknown) best = std::max(best, static_cast<int>(std::lround(CellProbability(c) * 100.0f)));
    }
  }
  return best < 0 ? 255 : static_cast<std::uint8_t>(best);
}

// A box of cells coarsened by the smallest whole factor that brings it to at most max_cells.
struct CoarseLayout {
  int factor = 1;
  int columns = 0;
  int rows = 0;
};

CoarseLayout CoarsenToFit(const CellBox& box, std::size_t max_cells) {
  CoarseLayout layout;
  if (box.empty()) return layout;
  const auto cells = [&](int f) {
    return static_cast<std::size_t>((box.width() + f - 1) / f) * static_cast<std::size_t>((box.height() + f - 1) / f);
  };
  while (cells(layout.factor) > std::max<std::size_t>(max_cells, 1)) ++layout.factor;
  layout.columns = (box.width() + layout.factor - 1) / layout.factor;
  layout.rows = (box.height() + layout.factor - 1) / layout.factor;
  return layout;
}

// A foxglove.Grid message in the map frame whose origin is the cell (x0, y0) of the given
// resolution, lifted by z so that overlays draw above the map.
std::string GridMessage(std::uint64_t ns, const CellBox& box, double resolution, double z, const CoarseLayout& layout,
                        int stride, json fields, const std::string& data) {
  const double x0 = box.empty() ? 0.0 : box.min.x() * resolution, y0 = box.empty() ? 0.0 : box.min.y() * resolution;
  const double cell = resolution * layout.factor;
  return Dump({{"timestamp", Time(ns)},
               {"frame_id", kFoxgloveMapFrame},
               {"pose", {{"position", {{"x", x0}, {"y", y0}, {"z", z}}}, {"orientation", Yaw(0.0)}}},
               {"column_count", layout.columns},
               {"cell_size", {{"x", cell}, {"y", cell}}},
               {"row_stride", layout.columns * stride},
               {"cell_stride", stride},
               {"fields", std::move(fields)},
               {"data", Base64Encode(data)}});
}

}  // namespace

FoxgloveTopicInfo TopicInfo(FoxgloveTopic topic) {
  switch (topic) {
    case FoxgloveTopic::kMap: return {"map", "foxglove.Grid"};
    case FoxgloveTopic::kRobot: return {"robot", "foxglove.PoseInFrame"};
    case FoxgloveTopic::kScan: return {"scan", "foxglove.LaserScan"};
    case FoxgloveTopic::kTrajectory: return {"trajectory", "foxglove.PosesInFrame"};
    case FoxgloveTopic::kParticles: return {"particles", "foxglove.PosesInFrame"};
    case FoxgloveTopic::kTransform: return {"tf", "foxglove.FrameTransform"};
    case FoxgloveTopic::kStats: return {"stats", "pslam.Stats"};
    case FoxgloveTopic::kExploration: return {"exploration", "foxglove.SceneUpdate"};
    case FoxgloveTopic::kPrediction: return {"prediction", "foxglove.Grid"};
  }
  return {"", ""};
}

const std::string& TopicSchema(FoxgloveTopic topic) {
  static const std::array<std::string, kFoxgloveTopics.size()> schemas = [] {
    std::array<std::string, kFoxgloveTopics.size()> s;
    for (std::size_t i = 0; i < s.size(); ++i) s[i] = Dump(SchemaOf(kFoxgloveTopics[i]));
    return s;
  }();
  return schemas[static_cast<std::size_t>(topic)];
}

std::string RobotFrame(const std::string& session_id) { return session_id + "/base_link"; }

json ChannelJson(std::uint32_t id, const std::string& session_id, FoxgloveTopic topic) {
  const FoxgloveTopicInfo info = TopicInfo(topic);
  return {{"id", id},
          {"topic", "/" + session_id + "/" + info.suffix},
          {"encoding", "json"},
          {"schemaName", info.schema_name},
          {"schema", TopicSchema(topic)},
          {"schemaEncoding", "jsonschema"}};
}

std::array<std::uint8_t, kFoxgloveMessageHeader> MessageDataHeader(std::uint32_t subscription, std::uint64_t ns) {
  std::array<std::uint8_t, kFoxgloveMessageHeader> h{};
  h[0] = 0x01;
  for (int i = 0; i < 4; ++i) h[1 + i] = static_cast<std::uint8_t>(subscription >> (8 * i));  // little-endian
  for (int i = 0; i < 8; ++i) h[5 + i] = static_cast<std::uint8_t>(ns >> (8 * i));
  return h;
}

std::string GridPayload(const OccupancyGrid& grid, std::uint64_t ns, std::size_t max_cells) {
  const CellBox known = grid.KnownBounds();
  const CoarseLayout layout = CoarsenToFit(known, max_cells);
  const int factor = layout.factor;
  constexpr int kStride = 3;
  std::string data(static_cast<std::size_t>(layout.columns) * static_cast<std::size_t>(layout.rows) * kStride, '\0');
  for (int r = 0; r < layout.rows; ++r) {
    for (int c = 0; c < layout.columns; ++c) {
      const std::uint8_t occupancy = BlockOccupancy(grid, known.min.x() + c * factor, known.min.y() + r * factor, factor);
      const std::size_t at =
          (static_cast<std::size_t>(r) * static_cast<std::size_t>(layout.columns) + static_cast<std::size_t>(c)) * kStride;
      const bool unknown = occupancy == 255;
      data[at] = static_cast<char>(occupancy);
      data[at + 1] = static_cast<char>(unknown ? 0 : 255 - std::lround(occupancy * 2.55));  // free white, walls black
      data[at + 2] = static_cast<char>(unknown ? 0 : 255);
    }
  }
  constexpr int kUint8 = 1;  // foxglove.NumericType
  json fields = json::array({{{"name", "occupancy"}, {"offset", 0}, {"type", kUint8}},
                             {{"name", "red"}, {"offset", 1}, {"type", kUint8}},
                             {{"name", "green"}, {"offset", 1}, {"type", kUint8}},
                             {{"name", "blue"}, {"offset", 1}, {"type", kUint8}},
                             {{"name", "alpha"}, {"offset", 2}, {"type", kUint8}}});
  return GridMessage(ns, known, grid.resolution(), 0.0, layout, kStride, std::move(fields), data);
}

std::string PredictionPayload(const std::vector<const HypothesisRecord*>& hypotheses, double resolution,
                              std::uint64_t ns, std::size_t max_cells) {
  CellBox box;
  for (const HypothesisRecord* h : hypotheses) {
    for (const PredictedCell& c : h->cells) box.Extend({c.x, c.y});
  }
  const CoarseLayout layout = CoarsenToFit(box, max_cells);
  const int factor = layout.factor;
  constexpr int kStride = 5;
  constexpr std::uint8_t kWallAlpha = 230, kFreeAlpha = 70;
  std::string data(static_cast<std::size_t>(layout.columns) * static_cast<std::size_t>(layout.rows) * kStride, '\0');
  for (const HypothesisRecord* h : hypotheses) {
    const auto psi = static_cast<char>(std::clamp(std::lround(h->psi * 100.0), 0L, 100L));
    for (const PredictedCell& c : h->cells) {
      const bool wall = c.occupancy >= 0.5f;
      const std::size_t at = (static_cast<std::size_t>((c.y - box.min.y()) / factor) * static_cast<std::size_t>(layout.columns) +
                              static_cast<std::size_t>((c.x - box.min.x()) / factor)) * kStride;
      if (static_cast<std::uint8_t>(data[at + 3]) >= (wall ? kWallAlpha : kFreeAlpha)) continue;  // a wall wins
      data[at] = static_cast<char>(wall ? 240 : 90);
      data[at + 1] = static_cast<char>(wall ? 90 : 170);
      data[at + 2] = static_cast<char>(wall ? 30 : 255);
      data[at + 3] = static_cast<char>(wall ? kWallAlpha : kFreeAlpha);
      data[at + 4] = psi;
    }
  }
  constexpr int kUint8 = 1;  // foxglove.NumericType
  json fields = json::array({{{"name", "red"}, {"offset", 0}, {"type", kUint8}},
                             {{"name", "green"}, {"offset", 1}, {"type", kUint8}},
                             {{"name", "blue"}, {"offset", 2}, {"type", kUint8}},
                             {{"name", "alpha"}, {"offset", 3}, {"type", kUint8}},
                             {{"name", "psi"}, {"offset", 4}, {"type", kUint8}}});
  return GridMessage(ns, box, resolution, 0.01, layout, kStride, std::move(fields), data);  // above the map
}

std::string PoseInFramePayload(const Pose2D& pose, std::uint64_t ns) {
  return Dump({{"timestamp", Time(ns)}, {"frame_id", kFoxgloveMapFrame}, {"pose", PoseJson(pose.x, pose.y, pose.theta)}});
}

std::string TransformPayload(const std::string& session_id, const Pose2D& robot, std::uint64_t ns) {
  return Dump({{"timestamp", Time(ns)},
               {"parent_frame_id", kFoxgloveMapFrame},
               {"child_frame_id", RobotFrame(session_id)},
               {"translation", Vector3(robot.x, robot.y)},
               {"rotation", Yaw(robot.theta)}});
}

std::string LaserScanPayload(const LaserScan& scan, const Pose2D& robot, std::uint64_t ns) {
  const Pose2D sensor = robot * scan.sensor_offset;
  json ranges = json::array();
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    // No return: a range the panel does not draw (it skips values outside min..max range; +inf is
    // not JSON, so the sensor's maximum stands for it).
    ranges.push_back(scan.IsReturn(i) ? Metres(scan.ranges[i]) : Metres(scan.max_range));
  }
  const double end = scan.ranges.empty() ? scan.angle_min : scan.BeamAngle(scan.ranges.size() - 1);
  return Dump({{"timestamp", Time(ns)},
               {"frame_id", kFoxgloveMapFrame},
               {"pose", PoseJson(sensor.x, sensor.y, sensor.theta)},
               {"start_angle", Unit(scan.angle_min)},
               {"end_angle", Unit(end)},
               {"ranges", std::move(ranges)},
               {"intensities", json::array()}});
}

std::string PosesInFramePayload(std::span<const Pose2D> poses, std::uint64_t ns, std::size_t max_poses) {
  json list = json::array();
  const std::size_t step = poses.size() <= max_poses ? 1 : (poses.size() + max_poses - 1) / max_poses;
  for (std::size_t i = 0; i < poses.size(); i += step) list.push_back(PoseJson(poses[i].x, poses[i].y, poses[i].theta));
  if (!poses.empty() && (poses.size() - 1) % step != 0) {
    list.push_back(PoseJson(poses.back().x, poses.back().y, poses.back().theta));  // the latest always
  }
  return Dump({{"timestamp", Time(ns)}, {"frame_id", kFoxgloveMapFrame}, {"poses", std::move(list)}});
}

std::string StatsPayload(const EngineStats& stats) { return Dump(EngineStatsToJson(stats)); }

std::string ExplorationPayload(const std::vector<std::array<double, 2>>& frontiers,
                               const std::optional<ExplorationTarget>& target, std::uint64_t ns) {
  json spheres = json::array(), lines = json::array();
  for (const auto& f : frontiers) spheres.push_back(Sphere(f[0], f[1], 0.15, Color(0.1, 0.6, 1.0, 0.9)));
  if (target) {
    spheres.push_back(Sphere(target->x, target->y, 0.4, Color(1.0, 0.5, 0.0, 0.9)));
    json points = json::array();
    for (const auto& p : target->path) points.push_back(Vector3(p[0], p[1]));
    if (points.size() >= 2) {
      lines.push_back({{"type", 0},  // LINE_STRIP
                       {"pose", PoseJson(0.0, 0.0, 0.0)},
                       {"thickness", 0.05},
                       {"scale_invariant", false},
                       {"points", std::move(points)},
                       {"color", Color(1.0, 0.5, 0.0, 0.9)},
                       {"colors", json::array()},
                       {"indices", json::array()}});
    }
  }
  const json none = json::array();
  json entity = {{"timestamp", Time(ns)}, {"frame_id", kFoxgloveMapFrame}, {"id", "exploration"},
                 {"lifetime", {{"sec", 0}, {"nsec", 0}}}, {"frame_locked", false}, {"metadata", none},
                 {"arrows", none}, {"cubes", none}, {"spheres", std::move(spheres)}, {"cylinders", none},
                 {"lines", std::move(lines)}, {"triangles", none}, {"texts", none}, {"models", none}};
  return Dump({{"deletions", none}, {"entities", json::array({std::move(entity)})}});
}

}  // namespace pslam::server
