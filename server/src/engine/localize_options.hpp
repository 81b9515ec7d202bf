#pragma once
// Localize mode's Monte Carlo localization options from a session's settings.
#include "model/session_settings.hpp"
#include "pslam/localize/mcl_options.hpp"

namespace pslam::server {

// More particles than this would cost seconds per scan and gigabytes: refused.
inline constexpr int kMaxLocalizeParticles = 200000;

// The core's defaults, overridden by settings.localization_json (option names as
// SetMclOption takes them), seeded by settings.seed. Throws std::invalid_argument naming the
// option on an unknown name, a bad value or inconsistent options.
MclOptions ToMclOptions(const SessionSettings& settings);

}  // namespace pslam::server
