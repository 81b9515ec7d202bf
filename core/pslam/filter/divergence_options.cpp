#include "pslam/filter/divergence_options.hpp"

#include "pslam/common/option_table.hpp"

namespace pslam {
namespace {

const OptionTable<DivergenceOptions>& Setters() {
  static const OptionTable<DivergenceOptions> setters = {
      {"collapse_window", Option(&DivergenceOptions::collapse_window)},
      {"score_lost", Option(&DivergenceOptions::score_lost)},
      {"weak_window", Option(&DivergenceOptions::weak_window)},
      {"score_degraded", Option(&DivergenceOptions::score_degraded)},
      {"neff_pinned", Option(&DivergenceOptions::neff_pinned)},
      {"neff_pinned_updates", Option(&DivergenceOptions::neff_pinned_updates)},
      {"jump_translation", Option(&DivergenceOptions::jump_translation)},
      {"jump_rotation", Option(&DivergenceOptions::jump_rotation)},
      {"jump_slip_speed", Option(&DivergenceOptions::jump_slip_speed)},
      {"jump_slip_turn_rate", Option(&DivergenceOptions::jump_slip_turn_rate)},
      {"jump_hold_seconds", Option(&DivergenceOptions::jump_hold_seconds)},
      {"recover_seconds", Option(&DivergenceOptions::recover_seconds)},
  };
  return setters;
}

}  // namespace

std::string SetDivergenceOption(DivergenceOptions& options, const std::string& name, const std::string& value) {
  return SetOption(Setters(), options, name, value);
}

std::vector<std::string> DivergenceOptionNames() {
  return OptionNames(Setters());
}

}  // namespace pslam
