#pragma once
// JSON forms of the session settings and the laser geometry (hello.laser, hello.settings, replay
// settings, the sessions table). Parsing is strict: unknown keys, wrong types and out-of-range
// values throw ApiError(400) naming the field.
#include <nlohmann/json.hpp>

#include "model/session_settings.hpp"

namespace pslam::server {

struct SettingsLimits {
  int max_particles = 1000;
  int max_beams = 8192;
  int max_threads = 16;
  int max_memory_mb = 65536;  // per session
};

// 'defaults' overridden by the fields present in 'json' (which may be null: no overrides).
SessionSettings ParseSessionSettings(const nlohmann::json& json, const SessionSettings& defaults,
                                     const SettingsLimits& limits, const std::string& where = "settings");
nlohmann::json SessionSettingsToJson(const SessionSettings& settings);

// {"x", "y", "theta", "std_xy", "std_theta"}: x and y required.
InitialPose ParseInitialPose(const nlohmann::json& json, const std::string& where);
nlohmann::json InitialPoseToJson(const InitialPose& pose);

LaserGeometry ParseLaserGeometry(const nlohmann::json& json, const SettingsLimits& limits,
                                 const std::string& where = "laser");
nlohmann::json LaserGeometryToJson(const LaserGeometry& laser);

}  // namespace pslam::server
