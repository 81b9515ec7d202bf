#pragma once
// Builds the scan source the options name (and connects its devices).
#include <memory>

#include "agent_options.hpp"
#include "sources/scan_source.hpp"

namespace pslam::agent {

// Throws std::runtime_error with a clear message when the source cannot be opened.
std::unique_ptr<ScanSource> MakeSource(const AgentOptions& options);

}  // namespace pslam::agent
