#include "engine/localize_options.hpp"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace pslam::server {

MclOptions ToMclOptions(const SessionSettings& settings) {
  MclOptions o;
  o.seed = settings.seed;
  const nlohmann::json j =
      nlohmann::json::parse(settings.localization_json.empty() ? "{}" : settings.localization_json);
  for (const auto& [name, value] : j.items()) {
    if (!value.is_number() && !value.is_boolean()) throw std::invalid_argument("'" + name + "' must be a number");
    const std::string problem = SetMclOption(o, name, value.dump());
    if (!problem.empty()) throw std::invalid_argument(problem);
  }
  if (const std::string problem = ValidateMclOptions(o); !problem.empty()) throw std::invalid_argument(problem);
  if (o.max_particles > kMaxLocalizeParticles) {
    throw std::invalid_argument("max_particles must be at most " + std::to_string(kMaxLocalizeParticles));
  }
  return o;
}

}  // namespace pslam::server
