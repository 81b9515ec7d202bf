#include "service/settings_codec.hpp"

#include <cmath>

#include "engine/localize_options.hpp"
#include "engine/slam_pipeline.hpp"

#include "service/json_fields.hpp"

namespace pslam::server {

SessionSettings ParseSessionSettings(const nlohmann::json& json, const SessionSettings& defaults,
                                     const SettingsLimits& limits, const std::string& where) {
  SessionSettings s = defaults;
  if (json.is_null()) return s;
  JsonFields f(json, where);
  if (auto v = f.Integer("particles")) {
    if (*v < 1 || *v > limits.max_particles) f.Fail("particles", "must be in [1, " + std::to_string(limits.max_particles) + "]");
    s.particles = static_cast<int>(*v);
  }
  if (auto v = f.Integer("seed")) {
    if (*v < 0) f.Fail("seed", "must not be negative");
    s.seed = static_cast<std::uint64_t>(*v);
  }
  if (auto v = f.Bool("predict")) s.predict = *v;
  if (auto v = f.Integer("threads")) {
    if (*v < 1 || *v > limits.max_threads) f.Fail("threads", "must be in [1, " + std::to_string(limits.max_threads) + "]");
    s.threads = static_cast<int>(*v);
  }
  if (auto v = f.Number("resolution_meters")) {
    if (*v < 0.01 || *v > 1.0) f.Fail("resolution_meters", "must be in [0.01, 1]");
    s.resolution = *v;
  }
  if (auto v = f.Number("linear_update_meters")) {
    if (*v < 0.0 || *v > 10.0) f.Fail("linear_update_meters", "must be in [0, 10]");
    s.linear_update = *v;
  }
  if (auto v = f.Number("angular_update_radians")) {
    if (*v < 0.0 || *v > 3.2) f.Fail("angular_update_radians", "must be in [0, 3.2]");
    s.angular_update = *v;
  }
  if (auto v = f.Number("resample_threshold")) {
    if (*v <= 0.0 || *v > 1.0) f.Fail("resample_threshold", "must be in (0, 1]");
    s.resample_threshold = *v;
  }
  if (auto v = f.Number("degenerate_ratio")) {
    if (*v < 0.0 || *v >= 1.0) f.Fail("degenerate_ratio", "must be in [0, 1)");
    s.degenerate_ratio = *v;
  }
  if (auto v = f.Number("odometry_prior")) {
    if (*v < 0.0 || *v > 1000.0) f.Fail("odometry_prior", "must be in [0, 1000]");
    s.odometry_prior = *v;
  }
  if (auto v = f.Bool("hit_offsets")) s.hit_offsets = *v;
  if (auto v = f.Integer("memory_limit_mb")) {
    if (*v < 16 || *v > limits.max_memory_mb) f.Fail("memory_limit_mb", "must be in [16, " + std::to_string(limits.max_memory_mb) + "]");
    s.memory_limit_mb = static_cast<int>(*v);
  }
  if (const nlohmann::json* p = f.Object("predictor")) s.predictor_json = p->dump();
  if (auto v = f.String("mode")) {
    if (*v != "map" && *v != "localize" && *v != "extend") f.Fail("mode", "must be \"map\", \"localize\" or \"extend\"");
    s.mode = *v;
  }
  if (auto v = f.String("site", 64)) s.site = *v;
  if (auto v = f.Integer("map_version")) {
    if (*v < 1) f.Fail("map_version", "must be at least 1");
    s.map_version = *v;
  }
  if (const nlohmann::json* p = f.Object("initial_pose")) s.initial_pose = ParseInitialPose(*p, where + ".initial_pose");
  if (const nlohmann::json* p = f.Object("localization")) s.localization_json = p->dump();
  f.RejectUnknown();
  if (s.mode != "map" && s.site.empty()) f.Fail("site", "is required in " + s.mode + " mode (the site whose map to localize on)");
  if (s.map_version > 0 && s.site.empty()) f.Fail("map_version", "needs a 'site'");
  if (s.mode != "map") {
    try {
      ToMclOptions(s);
    } catch (const std::exception& e) {
      f.Fail("localization", std::string("is invalid: ") + e.what());
    }
  }
  // The engine builds its P-SLAM from these settings; refuse them here, while the client can still
  // be told, rather than when the session starts.
  try {
    ToPSlamOptions(s);
  } catch (const std::exception& e) {
    f.Fail("predictor", std::string("is invalid: ") + e.what());
  }
  return s;
}

InitialPose ParseInitialPose(const nlohmann::json& json, const std::string& where) {
  JsonFields f(json, where);
  InitialPose p;
  p.x = f.RequiredNumber("x");
  p.y = f.RequiredNumber("y");
  p.theta = f.NumberOr("theta", 0.0);
  p.std_xy = f.NumberOr("std_xy", p.std_xy);
  p.std_theta = f.NumberOr("std_theta", p.std_theta);
  f.RejectUnknown();
  if (std::abs(p.x) > 1e6 || std::abs(p.y) > 1e6) f.Fail("x", "and y must be within 1000 km of the origin");
  if (std::abs(p.theta) > 100.0) f.Fail("theta", "must be in [-100, 100] rad");
  if (p.std_xy < 0.0 || p.std_xy > 100.0) f.Fail("std_xy", "must be in [0, 100] m");
  if (p.std_theta < 0.0 || p.std_theta > 10.0) f.Fail("std_theta", "must be in [0, 10] rad");
  return p;
}

nlohmann::json InitialPoseToJson(const InitialPose& p) {
  return {{"x", p.x}, {"y", p.y}, {"theta", p.theta}, {"std_xy", p.std_xy}, {"std_theta", p.std_theta}};
}

nlohmann::json SessionSettingsToJson(const SessionSettings& s) {
  const auto object = [](const std::string& text) {
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    return j.is_object() ? j : nlohmann::json::object();
  };
  return {{"particles", s.particles},
          {"seed", s.seed},
          {"predict", s.predict},
          {"threads", s.threads},
          {"resolution_meters", s.resolution},
          {"linear_update_meters", s.linear_update},
          {"angular_update_radians", s.angular_update},
          {"resample_threshold", s.resample_threshold},
          {"degenerate_ratio", s.degenerate_ratio},
          {"odometry_prior", s.odometry_prior},
          {"hit_offsets", s.hit_offsets},
          {"memory_limit_mb", s.memory_limit_mb},
          {"predictor", object(s.predictor_json)},
          {"mode", s.mode},
          {"site", s.site.empty() ? nlohmann::json() : nlohmann::json(s.site)},
          {"map_version", s.map_version > 0 ? nlohmann::json(s.map_version) : nlohmann::json()},
          {"initial_pose", s.initial_pose ? InitialPoseToJson(*s.initial_pose) : nlohmann::json()},
          {"localization", object(s.localization_json)}};
}

LaserGeometry ParseLaserGeometry(const nlohmann::json& json, const SettingsLimits& limits, const std::string& where) {
  JsonFields f(json, where);
  LaserGeometry l;
  l.angle_min = f.RequiredNumber("angle_min");
  l.angle_increment = f.RequiredNumber("angle_increment");
  const std::int64_t beams = f.RequiredInteger("beams");
  l.max_range = f.RequiredNumber("max_range");
  l.min_range = f.NumberOr("min_range", 0.0);
  if (const nlohmann::json* offset = f.Object("offset")) {
    JsonFields o(*offset, where + ".offset");
    l.offset_x = o.NumberOr("x", 0.0);
    l.offset_y = o.NumberOr("y", 0.0);
    l.offset_theta = o.NumberOr("theta", 0.0);
    o.RejectUnknown();
  }
  f.RejectUnknown();
  if (beams < 1 || beams > limits.max_beams) f.Fail("beams", "must be in [1, " + std::to_string(limits.max_beams) + "]");
  l.beams = static_cast<int>(beams);
  if (l.angle_increment == 0.0 || std::abs(l.angle_increment) > 1.0) f.Fail("angle_increment", "must be non-zero and at most 1 rad");
  if (std::abs(l.angle_min) > 7.0) f.Fail("angle_min", "must be in [-7, 7] rad");
  if (l.max_range <= 0.0 || l.max_range > 1000.0) f.Fail("max_range", "must be in (0, 1000] m");
  if (l.min_range < 0.0 || l.min_range >= l.max_range) f.Fail("min_range", "must be in [0, max_range)");
  // A sensor mounted metres off the robot is a unit mistake, and would move every scan that far.
  if (std::abs(l.offset_x) > 10.0 || std::abs(l.offset_y) > 10.0) f.Fail("offset", "x and y must be in [-10, 10] m");
  if (std::abs(l.offset_theta) > 7.0) f.Fail("offset", "theta must be in [-7, 7] rad");
  return l;
}

nlohmann::json LaserGeometryToJson(const LaserGeometry& l) {
  return {{"angle_min", l.angle_min},
          {"angle_increment", l.angle_increment},
          {"beams", l.beams},
          {"max_range", l.max_range},
          {"min_range", l.min_range},
          {"offset", {{"x", l.offset_x}, {"y", l.offset_y}, {"theta", l.offset_theta}}}};
}

}  // namespace pslam::server
