// Session settings and laser geometry (hello.settings, hello.laser, replay requests): any JSON must
// be accepted or refused with ApiError(400). Accepted settings survive their JSON round trip.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "service/api_error.hpp"
#include "service/settings_codec.hpp"

using namespace pslam::server;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nlohmann::json json = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) return 0;
  const SettingsLimits limits;
  try {
    const SessionSettings settings = ParseSessionSettings(json, SessionSettings{}, limits);
    const SessionSettings again = ParseSessionSettings(SessionSettingsToJson(settings), SessionSettings{}, limits);
    if (again.particles != settings.particles || again.seed != settings.seed || again.threads != settings.threads ||
        again.resolution != settings.resolution || again.predict != settings.predict) {
      std::abort();
    }
  } catch (const ApiError& e) {
    if (e.status() != 400) std::abort();
  }
  try {
    const LaserGeometry laser = ParseLaserGeometry(json, limits);
    if (laser.beams < 1 || laser.beams > limits.max_beams) std::abort();
    (void)ParseLaserGeometry(LaserGeometryToJson(laser), limits);
  } catch (const ApiError& e) {
    if (e.status() != 400) std::abort();
  }
  return 0;
}
