#include "pslam/localize/mcl_options.hpp"

#include "pslam/common/option_table.hpp"

namespace pslam {
namespace {

const OptionTable<MclOptions>& Setters() {
  using L = LikelihoodFieldOptions;
  static const OptionTable<MclOptions> setters = {
      {"min_particles", Option(&MclOptions::min_particles)},
      {"max_particles", Option(&MclOptions::max_particles)},
      {"kld_err", Option(&MclOptions::kld_err)},
      {"kld_z", Option(&MclOptions::kld_z)},
      {"bin_size_xy", Option(&MclOptions::bin_size_xy)},
      {"bin_size_theta", Option(&MclOptions::bin_size_theta)},
      {"update_min_d", Option(&MclOptions::update_min_d)},
      {"update_min_a", Option(&MclOptions::update_min_a)},
      {"resample_threshold", Option(&MclOptions::resample_threshold)},
      {"recovery_alpha_slow", Option(&MclOptions::recovery_alpha_slow)},
      {"recovery_alpha_fast", Option(&MclOptions::recovery_alpha_fast)},
      {"recovery_min_drop", Option(&MclOptions::recovery_min_drop)},
      {"localized_weight", Option(&MclOptions::localized_weight)},
      {"localized_position_std", Option(&MclOptions::localized_position_std)},
      {"localized_heading_std", Option(&MclOptions::localized_heading_std)},
      {"fill_unknown", Option(&MclOptions::fill_unknown)},
      {"fill_min_agreement", Option(&MclOptions::fill_min_agreement)},
      {"fill_min_checked", Option(&MclOptions::fill_min_checked)},
      {"refine", Option(&MclOptions::refine)},
      {"track_look_alikes", Option(&MclOptions::track_look_alikes)},
      {"refine_max_points", Option(&MclOptions::refine_max_points)},
      {"refine_gain", Option(&MclOptions::refine_gain)},
      {"refine_max_shift", Option(&MclOptions::refine_max_shift)},
      {"refine_max_turn", Option(&MclOptions::refine_max_turn)},
      {"seed", Option(&MclOptions::seed)},
      {"scan_odometry.enabled", Option(&MclOptions::scan_odometry, &ScanOdometryOptions::enabled)},
      {"scan_odometry.scans_per_map", Option(&MclOptions::scan_odometry, &ScanOdometryOptions::scans_per_map)},
      {"scan_odometry.min_constrained_ratio", Option(&MclOptions::scan_odometry, &ScanOdometryOptions::min_constrained_ratio)},
      {"place.enabled", Option(&MclOptions::place, &PlaceRecognitionOptions::enabled)},
      {"place.cloud_travel", Option(&MclOptions::place, &PlaceRecognitionOptions::cloud_travel)},
      {"place.max_points", Option(&MclOptions::place, &PlaceRecognitionOptions::max_points)},
      {"place.first_search_after", Option(&MclOptions::place, &PlaceRecognitionOptions::first_search_after)},
      {"place.search_every", Option(&MclOptions::place, &PlaceRecognitionOptions::search_every)},
      {"place.search_resolution", Option(&MclOptions::place, &PlaceRecognitionOptions::search_resolution)},
      {"place.min_score", Option(&MclOptions::place, &PlaceRecognitionOptions::min_score)},
      {"place.ambiguity_ratio", Option(&MclOptions::place, &PlaceRecognitionOptions::ambiguity_ratio)},
      {"place.ambiguity_distance", Option(&MclOptions::place, &PlaceRecognitionOptions::ambiguity_distance)},
      {"place.ambiguity_ratio_in_place", Option(&MclOptions::place, &PlaceRecognitionOptions::ambiguity_ratio_in_place)},
      {"place.in_place_travel", Option(&MclOptions::place, &PlaceRecognitionOptions::in_place_travel)},
      {"motion.rotation_per_rotation", Option(&MclOptions::motion, &MotionNoise::rotation_per_rotation)},
      {"motion.rotation_per_translation", Option(&MclOptions::motion, &MotionNoise::rotation_per_translation)},
      {"motion.translation_per_translation", Option(&MclOptions::motion, &MotionNoise::translation_per_translation)},
      {"motion.translation_per_rotation", Option(&MclOptions::motion, &MotionNoise::translation_per_rotation)},
      {"likelihood.sigma", Option(&MclOptions::likelihood, &L::sigma)},
      {"likelihood.z_hit", Option(&MclOptions::likelihood, &L::z_hit)},
      {"likelihood.z_rand", Option(&MclOptions::likelihood, &L::z_rand)},
      {"likelihood.max_distance", Option(&MclOptions::likelihood, &L::max_distance)},
      {"likelihood.occupied_probability", Option(&MclOptions::likelihood, &L::occupied_probability)},
      {"likelihood.max_beams", Option(&MclOptions::likelihood, &L::max_beams)},
      {"likelihood.temperature", Option(&MclOptions::likelihood, &L::temperature)},
      {"likelihood.face_distance", Option(&MclOptions::likelihood, &L::face_distance)},
      {"likelihood.fill_clearance", Option(&MclOptions::likelihood, &L::fill_clearance)},
      {"points.max_usable_range", Option(&MclOptions::points, &ScanPointsOptions::max_usable_range)},
  };
  return setters;
}

}  // namespace

std::string SetMclOption(MclOptions& options, const std::string& name, const std::string& value) {
  return SetOption(Setters(), options, name, value, "localization option");
}

std::vector<std::string> MclOptionNames() {
  return OptionNames(Setters());
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
  if (!(l.fill_clearance >= 0.0) || l.fill_clearance > 10.0) return "likelihood.fill_clearance must be in [0, 10] m";
  if (!(l.temperature > 0.0) || l.max_beams < 1) return "need likelihood.temperature > 0 and max_beams >= 1";
  if (!(l.occupied_probability > 0.5 && l.occupied_probability < 1.0)) return "need 0.5 < likelihood.occupied_probability < 1";
  if (!(o.fill_min_agreement >= 0.0 && o.fill_min_agreement <= 1.0) || o.fill_min_checked < 0) {
    return "need 0 <= fill_min_agreement <= 1 and fill_min_checked >= 0";
  }
  if (!(o.refine_gain > 0.0 && o.refine_gain <= 1.0)) return "need 0 < refine_gain <= 1";
  if (o.refine_max_points < 1 || !(o.refine_max_shift >= 0.0) || !(o.refine_max_turn >= 0.0))
    return "need refine_max_points >= 1 and non-negative refine bounds";
  if (o.scan_odometry.scans_per_map < 1 || o.scan_odometry.scans_per_map > 10000) return "need 1 <= scan_odometry.scans_per_map <= 10000";
  if (!(o.scan_odometry.min_constrained_ratio >= 0.0 && o.scan_odometry.min_constrained_ratio <= 1.0))
    return "need 0 <= scan_odometry.min_constrained_ratio <= 1";
  const PlaceRecognitionOptions& p = o.place;
  // Bounded so that no setting makes one search take minutes (its cost grows with the points, and
  // with the inverse cube of the resolution).
  if (!(p.cloud_travel > 0.0 && p.cloud_travel <= 100.0) || p.max_points < 10 || p.max_points > 2000)
    return "need 0 < place.cloud_travel <= 100 m and 10 <= place.max_points <= 2000";
  if (!(p.search_resolution >= 0.05 && p.search_resolution <= 1.0)) return "need 0.05 <= place.search_resolution <= 1 m";
  if (!(p.first_search_after >= 0.0) || !(p.search_every >= 0.5)) return "need place.first_search_after >= 0 and place.search_every >= 0.5 m";
  if (!(p.min_score > 0.0 && p.min_score < 1.0) || !(p.ambiguity_ratio > 0.0 && p.ambiguity_ratio <= 1.0) || !(p.ambiguity_distance > 0.0))
    return "need 0 < place.min_score < 1, 0 < place.ambiguity_ratio <= 1 and place.ambiguity_distance > 0";
  if (!(p.ambiguity_ratio_in_place > 0.0 && p.ambiguity_ratio_in_place <= 1.0) || !(p.in_place_travel >= 0.0))
    return "need 0 < place.ambiguity_ratio_in_place <= 1 and place.in_place_travel >= 0";
  return "";
}

}  // namespace pslam
