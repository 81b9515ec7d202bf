#include "pslam/localize/mcl_options.hpp"

#include <charconv>
#include <functional>
#include <map>

namespace pslam {
namespace {

using Setter = std::function<std::string(MclOptions&, const std::string&)>;

template <typename T>
std::string ParseNumber(const std::string& text, T& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  if (ec != std::errc() || ptr != end) return "not a number: '" + text + "'";
  return "";
}

template <typename T>
Setter Field(T MclOptions::*member) {
  return [member](MclOptions& o, const std::string& v) { return ParseNumber(v, o.*member); };
}
template <typename Group, typename T>
Setter Nested(Group MclOptions::*group, T Group::*member) {
  return [group, member](MclOptions& o, const std::string& v) { return ParseNumber(v, (o.*group).*member); };
}

const std::map<std::string, Setter>& Setters() {
  using L = LikelihoodFieldOptions;
  static const std::map<std::string, Setter> setters = {
      {"min_particles", Field(&MclOptions::min_particles)},
      {"max_particles", Field(&MclOptions::max_particles)},
      {"kld_err", Field(&MclOptions::kld_err)},
      {"kld_z", Field(&MclOptions::kld_z)},
      {"bin_size_xy", Field(&MclOptions::bin_size_xy)},
      {"bin_size_theta", Field(&MclOptions::bin_size_theta)},
      {"update_min_d", Field(&MclOptions::update_min_d)},
      {"update_min_a", Field(&MclOptions::update_min_a)},
      {"resample_threshold", Field(&MclOptions::resample_threshold)},
      {"recovery_alpha_slow", Field(&MclOptions::recovery_alpha_slow)},
      {"recovery_alpha_fast", Field(&MclOptions::recovery_alpha_fast)},
      {"recovery_min_drop", Field(&MclOptions::recovery_min_drop)},
      {"localized_weight", Field(&MclOptions::localized_weight)},
      {"localized_position_std", Field(&MclOptions::localized_position_std)},
      {"localized_heading_std", Field(&MclOptions::localized_heading_std)},
      {"seed", Field(&MclOptions::seed)},
      {"motion.rotation_per_rotation", Nested(&MclOptions::motion, &MotionNoise::rotation_per_rotation)},
      {"motion.rotation_per_translation", Nested(&MclOptions::motion, &MotionNoise::rotation_per_translation)},
      {"motion.translation_per_translation", Nested(&MclOptions::motion, &MotionNoise::translation_per_translation)},
      {"motion.translation_per_rotation", Nested(&MclOptions::motion, &MotionNoise::translation_per_rotation)},
      {"likelihood.sigma", Nested(&MclOptions::likelihood, &L::sigma)},
      {"likelihood.z_hit", Nested(&MclOptions::likelihood, &L::z_hit)},
      {"likelihood.z_rand", Nested(&MclOptions::likelihood, &L::z_rand)},
      {"likelihood.max_distance", Nested(&MclOptions::likelihood, &L::max_distance)},
      {"likelihood.occupied_probability", Nested(&MclOptions::likelihood, &L::occupied_probability)},
      {"likelihood.max_beams", Nested(&MclOptions::likelihood, &L::max_beams)},
      {"likelihood.temperature", Nested(&MclOptions::likelihood, &L::temperature)},
      {"points.max_usable_range", Nested(&MclOptions::points, &ScanPointsOptions::max_usable_range)},
  };
  return setters;
}

}  // namespace

std::string SetMclOption(MclOptions& options, const std::string& name, const std::string& value) {
  const auto it = Setters().find(name);
  if (it == Setters().end()) return "unknown localization option '" + name + "'";
  const std::string error = it->second(options, value);
  return error.empty() ? error : name + ": " + error;
}

std::vector<std::string> MclOptionNames() {
  std::vector<std::string> names;
  for (const auto& [name, setter] : Setters()) names.push_back(name);
  return names;
}

std::string ValidateMclOptions(const MclOptions& o) {
  const LikelihoodFieldOptions& l = o.likelihood;
  if (o.min_particles < 1 || o.max_particles < o.min_particles) return "need 1 <= min_particles <= max_particles";
  if (o.max_particles > 1000000) return "max_particles above 1000000";
  if (!(o.kld_err > 0.0) || !(o.kld_z > 0.0 && o.kld_z < 10.0)) return "need kld_err > 0 and 0 < kld_z < 10";
  if (!(o.bin_size_xy > 0.0) || !(o.bin_size_theta > 0.0)) return "bin sizes must be positive";
  if (!(o.update_min_d >= 0.0) || !(o.update_min_a >= 0.0)) return "update thresholds must not be negative";
  if (!(o.recovery_alpha_slow >= 0.0) || !(o.recovery_alpha_fast <= 1.0) || o.recovery_alpha_fast < o.recovery_alpha_slow)
    return "need 0 <= recovery_alpha_slow <= recovery_alpha_fast <= 1";
  if (!(o.recovery_min_drop >= 0.0 && o.recovery_min_drop < 1.0)) return "need 0 <= recovery_min_drop < 1";
  if (!(l.sigma > 0.0) || !(l.z_hit > 0.0) || !(l.z_rand > 0.0)) return "likelihood sigma, z_hit and z_rand must be positive";
  if (!(l.max_distance > 0.0) || l.max_distance > 50.0) return "likelihood.max_distance must be in (0, 50] m";
  if (!(l.temperature > 0.0) || l.max_beams < 1) return "need likelihood.temperature > 0 and max_beams >= 1";
  if (!(l.occupied_probability > 0.5 && l.occupied_probability < 1.0)) return "need 0.5 < likelihood.occupied_probability < 1";
  return "";
}

}  // namespace pslam
