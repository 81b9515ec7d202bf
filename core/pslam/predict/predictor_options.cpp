#include "pslam/predict/predictor_options.hpp"

#include <cmath>
#include <sstream>

namespace pslam {
namespace {

// Collects the first failed check; the message names the field and its value.
class Checker {
 public:
  void Require(bool ok, const char* field, double value, const char* rule) {
    if (ok || error_) return;
    std::ostringstream msg;
    msg << "PredictorOptions." << field << " = " << value << ": " << rule;
    error_ = msg.str();
  }
  std::optional<std::string> error() const { return error_; }

 private:
  std::optional<std::string> error_;
};

bool Positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

std::optional<std::string> ValidatePredictorOptions(const PredictorOptions& o) {
  Checker c;
  // Upper bounds keep cell counts far from int overflow at any sane resolution.
  c.Require(Positive(o.region_size_m) && o.region_size_m <= 100.0, "region_size_m", o.region_size_m,
            "must lie in (0, 100]");
  c.Require(Positive(o.control_point_range_m) && o.control_point_range_m <= 100.0, "control_point_range_m",
            o.control_point_range_m, "must lie in (0, 100]");
  c.Require(std::isfinite(o.min_reference_distance_m) && o.min_reference_distance_m >= 0.0,
            "min_reference_distance_m", o.min_reference_distance_m, "must be >= 0");
  c.Require(o.max_reference_corners >= 1, "max_reference_corners", o.max_reference_corners, "must be >= 1");
  c.Require(o.max_library_maps >= 0, "max_library_maps", o.max_library_maps, "must be >= 0");
  c.Require(Positive(o.search_radius_m) && o.search_radius_m <= 1000.0, "search_radius_m", o.search_radius_m,
            "must lie in (0, 1000]");
  c.Require(o.similarity_threshold >= 0.4 && o.similarity_threshold <= 0.7, "similarity_threshold",
            o.similarity_threshold, "must lie in [0.4, 0.7], the range the paper validates");
  c.Require(std::isfinite(o.min_structure_m) && o.min_structure_m >= 0.0, "min_structure_m", o.min_structure_m,
            "must be >= 0");
  c.Require(o.tolerance_cells >= 0 && o.tolerance_cells <= 2, "tolerance_cells", o.tolerance_cells,
            "must be 0, 1 or 2");
  c.Require(o.refined_candidates >= 0, "refined_candidates", o.refined_candidates, "must be >= 0");
  c.Require(o.coarse_rescored >= 0, "coarse_rescored", o.coarse_rescored, "must be >= 0");
  c.Require(std::isfinite(o.ambiguity_margin) && o.ambiguity_margin >= 0.0 && o.ambiguity_margin <= 1.0,
            "ambiguity_margin", o.ambiguity_margin, "must lie in [0, 1]");
  c.Require(std::isfinite(o.ambiguity_agreement) && o.ambiguity_agreement >= 0.0 && o.ambiguity_agreement <= 1.0,
            "ambiguity_agreement", o.ambiguity_agreement, "must lie in [0, 1]");
  c.Require(o.states.free_below > 0.0 && o.states.free_below <= 0.5, "states.free_below", o.states.free_below,
            "must lie in (0, 0.5]");
  c.Require(o.states.occupied_above >= 0.5 && o.states.occupied_above < 1.0, "states.occupied_above",
            o.states.occupied_above, "must lie in [0.5, 1)");
  const FeatureOptions& f = o.features;
  c.Require(Positive(f.min_line_length_m), "features.min_line_length_m", f.min_line_length_m, "must be > 0");
  c.Require(std::isfinite(f.max_line_gap_m) && f.max_line_gap_m >= 0.0, "features.max_line_gap_m", f.max_line_gap_m,
            "must be >= 0");
  c.Require(f.hough_vote_fraction > 0.0 && f.hough_vote_fraction <= 1.0, "features.hough_vote_fraction",
            f.hough_vote_fraction, "must lie in (0, 1]");
  c.Require(Positive(f.corner_resolution_m), "features.corner_resolution_m", f.corner_resolution_m, "must be > 0");
  c.Require(Positive(f.blur_sigma_m), "features.blur_sigma_m", f.blur_sigma_m, "must be > 0");
  c.Require(f.corner_block_size >= 2, "features.corner_block_size", f.corner_block_size, "must be >= 2");
  c.Require(std::isfinite(f.harris_k) && f.harris_k > 0.0, "features.harris_k", f.harris_k, "must be > 0");
  c.Require(f.corner_quality > 0.0 && f.corner_quality < 1.0, "features.corner_quality", f.corner_quality,
            "must lie in (0, 1)");
  c.Require(Positive(f.corner_spacing_m), "features.corner_spacing_m", f.corner_spacing_m, "must be > 0");
  c.Require(f.max_corners >= 1, "features.max_corners", f.max_corners, "must be >= 1");
  c.Require(Positive(f.arm_search_radius_m), "features.arm_search_radius_m", f.arm_search_radius_m, "must be > 0");
  c.Require(Positive(f.min_arm_length_m), "features.min_arm_length_m", f.min_arm_length_m, "must be > 0");
  c.Require(f.arm_merge_angle_deg > 0.0 && f.arm_merge_angle_deg < 30.0, "features.arm_merge_angle_deg",
            f.arm_merge_angle_deg, "must lie in (0, 30)");
  return c.error();
}

}  // namespace pslam
