#include "pslam/filter/rbpf_options.hpp"

#include <charconv>
#include <functional>
#include <map>

namespace pslam {
namespace {

using Setter = std::function<std::string(RbpfOptions&, const std::string&)>;

template <typename T>
std::string ParseNumber(const std::string& text, T& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  if (ec != std::errc() || ptr != end) return "not a number: '" + text + "'";
  return "";
}

template <typename T>
Setter Field(T RbpfOptions::*member) {
  return [member](RbpfOptions& o, const std::string& v) { return ParseNumber(v, o.*member); };
}
template <typename Group, typename T>
Setter Nested(Group RbpfOptions::*group, T Group::*member) {
  return [group, member](RbpfOptions& o, const std::string& v) { return ParseNumber(v, (o.*group).*member); };
}
std::string ParseFlag(const std::string& text, bool& out) {
  if (text == "true" || text == "1") out = true;
  else if (text == "false" || text == "0") out = false;
  else return "not a boolean: '" + text + "'";
  return "";
}
Setter Flag(bool RbpfOptions::*member) {
  return [member](RbpfOptions& o, const std::string& v) { return ParseFlag(v, o.*member); };
}
template <typename Group>
Setter NestedFlag(Group RbpfOptions::*group, bool Group::*member) {
  return [group, member](RbpfOptions& o, const std::string& v) { return ParseFlag(v, (o.*group).*member); };
}

const std::map<std::string, Setter>& Setters() {
  static const std::map<std::string, Setter> setters = {
      {"particles", Field(&RbpfOptions::particles)},
      {"seed", Field(&RbpfOptions::seed)},
      {"resolution", Field(&RbpfOptions::resolution)},
      {"linear_update", Field(&RbpfOptions::linear_update)},
      {"angular_update", Field(&RbpfOptions::angular_update)},
      {"resample_threshold", Field(&RbpfOptions::resample_threshold)},
      {"likelihood_temperature", Field(&RbpfOptions::likelihood_temperature)},
      {"threads", Field(&RbpfOptions::threads)},
      {"use_predictions", Flag(&RbpfOptions::use_predictions)},
      {"recovery", Flag(&RbpfOptions::recovery)},
      {"hit_ratio_threshold", Field(&RbpfOptions::hit_ratio_threshold)},
      {"min_hypothesis_points", Field(&RbpfOptions::min_hypothesis_points)},
      {"points.max_usable_range", Nested(&RbpfOptions::points, &ScanPointsOptions::max_usable_range)},
      {"points.no_return_free_range", Nested(&RbpfOptions::points, &ScanPointsOptions::no_return_free_range)},
      {"points.min_point_spacing", Nested(&RbpfOptions::points, &ScanPointsOptions::min_point_spacing)},
      {"insert.hit_probability", Nested(&RbpfOptions::insert, &ScanInsertOptions::hit_probability)},
      {"insert.miss_probability", Nested(&RbpfOptions::insert, &ScanInsertOptions::miss_probability)},
      {"insert.min_probability", Nested(&RbpfOptions::insert, &ScanInsertOptions::min_probability)},
      {"insert.max_probability", Nested(&RbpfOptions::insert, &ScanInsertOptions::max_probability)},
      {"tracking_match.coarsest_level", Nested(&RbpfOptions::tracking_match, &ScanMatchOptions::coarsest_level)},
      {"tracking_match.iterations_per_level", Nested(&RbpfOptions::tracking_match, &ScanMatchOptions::iterations_per_level)},
      {"tracking_match.min_score", Nested(&RbpfOptions::tracking_match, &ScanMatchOptions::min_score)},
      {"tracking_match.max_correction_translation", Nested(&RbpfOptions::tracking_match, &ScanMatchOptions::max_correction_translation)},
      {"tracking_match.max_correction_rotation", Nested(&RbpfOptions::tracking_match, &ScanMatchOptions::max_correction_rotation)},
      {"tracking_match.degenerate_ratio", Nested(&RbpfOptions::tracking_match, &ScanMatchOptions::degenerate_ratio)},
      {"particle_match.degenerate_ratio", Nested(&RbpfOptions::particle_match, &ScanMatchOptions::degenerate_ratio)},
      {"particle_match.max_correction_translation", Nested(&RbpfOptions::particle_match, &ScanMatchOptions::max_correction_translation)},
      {"particle_match.max_correction_rotation", Nested(&RbpfOptions::particle_match, &ScanMatchOptions::max_correction_rotation)},
      {"particle_match.coarsest_level", Nested(&RbpfOptions::particle_match, &ScanMatchOptions::coarsest_level)},
      {"particle_match.iterations_per_level", Nested(&RbpfOptions::particle_match, &ScanMatchOptions::iterations_per_level)},
      {"particle_match.min_score", Nested(&RbpfOptions::particle_match, &ScanMatchOptions::min_score)},
      {"likelihood.sigma", Nested(&RbpfOptions::likelihood, &LikelihoodOptions::sigma)},
      {"likelihood.window_cells", Nested(&RbpfOptions::likelihood, &LikelihoodOptions::window_cells)},
      {"likelihood.point_step", Nested(&RbpfOptions::likelihood, &LikelihoodOptions::point_step)},
      {"likelihood.free_space_check", NestedFlag(&RbpfOptions::likelihood, &LikelihoodOptions::free_space_check)},
      {"motion.rotation_per_rotation", Nested(&RbpfOptions::motion, &MotionNoise::rotation_per_rotation)},
      {"motion.rotation_per_translation", Nested(&RbpfOptions::motion, &MotionNoise::rotation_per_translation)},
      {"motion.translation_per_translation", Nested(&RbpfOptions::motion, &MotionNoise::translation_per_translation)},
      {"motion.translation_per_rotation", Nested(&RbpfOptions::motion, &MotionNoise::translation_per_rotation)},
      {"loop_closure.enabled", NestedFlag(&RbpfOptions::loop_closure, &LoopClosureOptions::enabled)},
      {"loop_closure.nodes_per_submap", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::nodes_per_submap)},
      {"loop_closure.recent_submaps", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::recent_submaps)},
      {"loop_closure.check_every_nodes", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::check_every_nodes)},
      {"loop_closure.max_candidates", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::max_candidates)},
      {"loop_closure.context_nodes", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::context_nodes)},
      {"loop_closure.cloud_spacing", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::cloud_spacing)},
      {"loop_closure.cloud_max_range", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::cloud_max_range)},
      {"loop_closure.base_window", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::base_window)},
      {"loop_closure.window_per_metre", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::window_per_metre)},
      {"loop_closure.max_window", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::max_window)},
      {"loop_closure.base_angular_window", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::base_angular_window)},
      {"loop_closure.angular_window_per_metre", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::angular_window_per_metre)},
      {"loop_closure.max_angular_window", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::max_angular_window)},
      {"loop_closure.closure_length", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::closure_length)},
      {"loop_closure.rest_after_closure", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::rest_after_closure)},
      {"loop_closure.search_depth", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::search_depth)},
      {"loop_closure.min_score", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::min_score)},
      {"loop_closure.ambiguity_distance", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::ambiguity_distance)},
      {"loop_closure.ambiguity_angle", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::ambiguity_angle)},
      {"loop_closure.ambiguity_ratio", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::ambiguity_ratio)},
      {"loop_closure.odometry_sigma_xy", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::odometry_sigma_xy)},
      {"loop_closure.odometry_sigma_theta", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::odometry_sigma_theta)},
      {"loop_closure.loop_sigma_xy", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::loop_sigma_xy)},
      {"loop_closure.loop_sigma_theta", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::loop_sigma_theta)},
      {"loop_closure.huber_scale", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::huber_scale)},
      {"loop_closure.outlier_sigma", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::outlier_sigma)},
      {"loop_closure.optimize_every_nodes", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::optimize_every_nodes)},
      {"loop_closure.immediate_correction", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::immediate_correction)},
      {"loop_closure.rebuild_translation", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::rebuild_translation)},
      {"loop_closure.rebuild_rotation", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::rebuild_rotation)},
      {"loop_closure.cached_search_grids", Nested(&RbpfOptions::loop_closure, &LoopClosureOptions::cached_search_grids)},
  };
  return setters;
}

}  // namespace

void SetDegenerateRatio(RbpfOptions& options, double ratio) {
  options.tracking_match.degenerate_ratio = ratio;
  options.particle_match.degenerate_ratio = ratio;
}

std::string SetRbpfOption(RbpfOptions& options, const std::string& name, const std::string& value) {
  const auto it = Setters().find(name);
  if (it == Setters().end()) return "unknown option '" + name + "'";
  const std::string error = it->second(options, value);
  return error.empty() ? "" : name + ": " + error;
}

std::vector<std::string> RbpfOptionNames() {
  std::vector<std::string> names;
  for (const auto& [name, setter] : Setters()) names.push_back(name);
  return names;
}

}  // namespace pslam
