#include "pslam/filter/divergence_options.hpp"

#include <charconv>
#include <functional>
#include <map>

namespace pslam {
namespace {

using Setter = std::function<std::string(DivergenceOptions&, const std::string&)>;

template <typename T>
Setter Field(T DivergenceOptions::*member) {
  return [member](DivergenceOptions& o, const std::string& text) -> std::string {
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, o.*member);
    if (ec != std::errc() || ptr != end) return "not a number: '" + text + "'";
    return "";
  };
}

const std::map<std::string, Setter>& Setters() {
  static const std::map<std::string, Setter> setters = {
      {"collapse_window", Field(&DivergenceOptions::collapse_window)},
      {"score_lost", Field(&DivergenceOptions::score_lost)},
      {"weak_window", Field(&DivergenceOptions::weak_window)},
      {"score_degraded", Field(&DivergenceOptions::score_degraded)},
      {"neff_pinned", Field(&DivergenceOptions::neff_pinned)},
      {"neff_pinned_updates", Field(&DivergenceOptions::neff_pinned_updates)},
      {"jump_translation", Field(&DivergenceOptions::jump_translation)},
      {"jump_rotation", Field(&DivergenceOptions::jump_rotation)},
      {"jump_slip_speed", Field(&DivergenceOptions::jump_slip_speed)},
      {"jump_slip_turn_rate", Field(&DivergenceOptions::jump_slip_turn_rate)},
      {"jump_hold_seconds", Field(&DivergenceOptions::jump_hold_seconds)},
      {"recover_seconds", Field(&DivergenceOptions::recover_seconds)},
  };
  return setters;
}

}  // namespace

std::string SetDivergenceOption(DivergenceOptions& options, const std::string& name, const std::string& value) {
  const auto it = Setters().find(name);
  if (it == Setters().end()) return "unknown option '" + name + "'";
  const std::string error = it->second(options, value);
  return error.empty() ? "" : name + ": " + error;
}

std::vector<std::string> DivergenceOptionNames() {
  std::vector<std::string> names;
  for (const auto& [name, setter] : Setters()) names.push_back(name);
  return names;
}

}  // namespace pslam
