#include "pslam/filter/rbpf_options.hpp"

#include "pslam/common/option_table.hpp"

namespace pslam {
namespace {

const OptionTable<RbpfOptions>& Setters() {
  static const OptionTable<RbpfOptions> setters = {
      {"particles", Option(&RbpfOptions::particles)},
      {"seed", Option(&RbpfOptions::seed)},
      {"resolution", Option(&RbpfOptions::resolution)},
      {"linear_update", Option(&RbpfOptions::linear_update)},
      {"prior_max_probability", Option(&RbpfOptions::prior_max_probability)},
      {"prior_forget_depth", Option(&RbpfOptions::prior_forget_depth)},
      {"angular_update", Option(&RbpfOptions::angular_update)},
      {"resample_threshold", Option(&RbpfOptions::resample_threshold)},
      {"likelihood_temperature", Option(&RbpfOptions::likelihood_temperature)},
      {"threads", Option(&RbpfOptions::threads)},
      {"use_predictions", Option(&RbpfOptions::use_predictions)},
      {"recovery", Option(&RbpfOptions::recovery)},
      {"hit_ratio_threshold", Option(&RbpfOptions::hit_ratio_threshold)},
      {"min_hypothesis_points", Option(&RbpfOptions::min_hypothesis_points)},
      {"points.max_usable_range", Option(&RbpfOptions::points, &ScanPointsOptions::max_usable_range)},
      {"points.no_return_free_range", Option(&RbpfOptions::points, &ScanPointsOptions::no_return_free_range)},
      {"points.min_point_spacing", Option(&RbpfOptions::points, &ScanPointsOptions::min_point_spacing)},
      {"insert.hit_probability", Option(&RbpfOptions::insert, &ScanInsertOptions::hit_probability)},
      {"insert.miss_probability", Option(&RbpfOptions::insert, &ScanInsertOptions::miss_probability)},
      {"insert.min_probability", Option(&RbpfOptions::insert, &ScanInsertOptions::min_probability)},
      {"insert.max_probability", Option(&RbpfOptions::insert, &ScanInsertOptions::max_probability)},
      {"insert.grazing_stop", Option(&RbpfOptions::insert, &ScanInsertOptions::grazing_stop)},
      {"tracking_match.hit_offsets", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::hit_offsets)},
      {"particle_match.hit_offsets", Option(&RbpfOptions::particle_match, &ScanMatchOptions::hit_offsets)},
      {"tracking_match.coarsest_level", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::coarsest_level)},
      {"tracking_match.second_start_level", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::second_start_level)},
      {"tracking_match.second_start_margin", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::second_start_margin)},
      {"tracking_match.iterations_per_level", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::iterations_per_level)},
      {"tracking_match.min_score", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::min_score)},
      {"tracking_match.max_correction_translation", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::max_correction_translation)},
      {"tracking_match.max_correction_rotation", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::max_correction_rotation)},
      {"tracking_match.degenerate_ratio", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::degenerate_ratio)},
      {"particle_match.degenerate_ratio", Option(&RbpfOptions::particle_match, &ScanMatchOptions::degenerate_ratio)},
      {"tracking_match.prior_translation_weight", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::prior_translation_weight)},
      {"tracking_match.prior_rotation_weight", Option(&RbpfOptions::tracking_match, &ScanMatchOptions::prior_rotation_weight)},
      {"particle_match.prior_translation_weight", Option(&RbpfOptions::particle_match, &ScanMatchOptions::prior_translation_weight)},
      {"particle_match.prior_rotation_weight", Option(&RbpfOptions::particle_match, &ScanMatchOptions::prior_rotation_weight)},
      {"particle_match.max_correction_translation", Option(&RbpfOptions::particle_match, &ScanMatchOptions::max_correction_translation)},
      {"particle_match.max_correction_rotation", Option(&RbpfOptions::particle_match, &ScanMatchOptions::max_correction_rotation)},
      {"particle_match.coarsest_level", Option(&RbpfOptions::particle_match, &ScanMatchOptions::coarsest_level)},
      {"particle_match.iterations_per_level", Option(&RbpfOptions::particle_match, &ScanMatchOptions::iterations_per_level)},
      {"particle_match.min_score", Option(&RbpfOptions::particle_match, &ScanMatchOptions::min_score)},
      {"likelihood.sigma", Option(&RbpfOptions::likelihood, &LikelihoodOptions::sigma)},
      {"likelihood.window_cells", Option(&RbpfOptions::likelihood, &LikelihoodOptions::window_cells)},
      {"likelihood.point_step", Option(&RbpfOptions::likelihood, &LikelihoodOptions::point_step)},
      {"likelihood.free_space_check", Option(&RbpfOptions::likelihood, &LikelihoodOptions::free_space_check)},
      {"motion.rotation_per_rotation", Option(&RbpfOptions::motion, &MotionNoise::rotation_per_rotation)},
      {"motion.rotation_per_translation", Option(&RbpfOptions::motion, &MotionNoise::rotation_per_translation)},
      {"motion.translation_per_translation", Option(&RbpfOptions::motion, &MotionNoise::translation_per_translation)},
      {"motion.translation_per_rotation", Option(&RbpfOptions::motion, &MotionNoise::translation_per_rotation)},
      {"odometry_calibration.enabled", Option(&RbpfOptions::odometry_calibration, &OdometryCalibrationOptions::enabled)},
      {"odometry_calibration.min_constrained_ratio", Option(&RbpfOptions::odometry_calibration, &OdometryCalibrationOptions::min_constrained_ratio)},
      {"odometry_calibration.window_metres", Option(&RbpfOptions::odometry_calibration, &OdometryCalibrationOptions::window_metres)},
      {"odometry_calibration.window_radians", Option(&RbpfOptions::odometry_calibration, &OdometryCalibrationOptions::window_radians)},
      {"odometry_calibration.min_evidence_metres", Option(&RbpfOptions::odometry_calibration, &OdometryCalibrationOptions::min_evidence_metres)},
      {"odometry_calibration.min_evidence_radians", Option(&RbpfOptions::odometry_calibration, &OdometryCalibrationOptions::min_evidence_radians)},
      {"odometry_calibration.max_scale_error", Option(&RbpfOptions::odometry_calibration, &OdometryCalibrationOptions::max_scale_error)},
      {"loop_closure.enabled", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::enabled)},
      {"loop_closure.nodes_per_submap", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::nodes_per_submap)},
      {"loop_closure.recent_submaps", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::recent_submaps)},
      {"loop_closure.check_every_nodes", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::check_every_nodes)},
      {"loop_closure.max_candidates", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::max_candidates)},
      {"loop_closure.judge_across_submaps", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::judge_across_submaps)},
      {"loop_closure.context_nodes", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::context_nodes)},
      {"loop_closure.cloud_spacing", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::cloud_spacing)},
      {"loop_closure.cloud_max_range", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::cloud_max_range)},
      {"loop_closure.base_window", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::base_window)},
      {"loop_closure.window_per_metre", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::window_per_metre)},
      {"loop_closure.max_window", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::max_window)},
      {"loop_closure.base_angular_window", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::base_angular_window)},
      {"loop_closure.angular_window_per_metre", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::angular_window_per_metre)},
      {"loop_closure.max_angular_window", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::max_angular_window)},
      {"loop_closure.closure_length", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::closure_length)},
      {"loop_closure.rest_after_closure", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::rest_after_closure)},
      {"loop_closure.search_depth", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::search_depth)},
      {"loop_closure.min_score", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::min_score)},
      {"loop_closure.ambiguity_distance", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::ambiguity_distance)},
      {"loop_closure.ambiguity_angle", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::ambiguity_angle)},
      {"loop_closure.ambiguity_ratio", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::ambiguity_ratio)},
      {"loop_closure.min_rival_window", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::min_rival_window)},
      {"loop_closure.odometry_sigma_xy", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::odometry_sigma_xy)},
      {"loop_closure.odometry_sigma_theta", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::odometry_sigma_theta)},
      {"loop_closure.loop_sigma_xy", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::loop_sigma_xy)},
      {"loop_closure.loop_sigma_theta", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::loop_sigma_theta)},
      {"loop_closure.huber_scale", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::huber_scale)},
      {"loop_closure.outlier_sigma", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::outlier_sigma)},
      {"loop_closure.optimize_every_nodes", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::optimize_every_nodes)},
      {"loop_closure.immediate_correction", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::immediate_correction)},
      {"loop_closure.rebuild_translation", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::rebuild_translation)},
      {"loop_closure.rebuild_rotation", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::rebuild_rotation)},
      {"loop_closure.cached_search_grids", Option(&RbpfOptions::loop_closure, &LoopClosureOptions::cached_search_grids)},
  };
  return setters;
}

}  // namespace

void SetDegenerateRatio(RbpfOptions& options, double ratio) {
  options.tracking_match.degenerate_ratio = ratio;
  options.particle_match.degenerate_ratio = ratio;
}

void SetMatchPrior(RbpfOptions& options, double translation_weight, double rotation_weight) {
  for (ScanMatchOptions* match : {&options.tracking_match, &options.particle_match}) {
    match->prior_translation_weight = translation_weight;
    match->prior_rotation_weight = rotation_weight;
  }
}

void SetHitOffsets(RbpfOptions& options, bool enabled) {
  options.tracking_match.hit_offsets = enabled;
  options.particle_match.hit_offsets = enabled;
}

std::string SetRbpfOption(RbpfOptions& options, const std::string& name, const std::string& value) {
  return SetOption(Setters(), options, name, value);
}

std::vector<std::string> RbpfOptionNames() {
  return OptionNames(Setters());
}

}  // namespace pslam
