#pragma once
// Writes P-SLAM's hypotheses and their status history as one JSON document (for `pslam run
// --hypotheses` and the experiments). Core has no JSON dependency: the format is flat enough to
// print by hand.
#include <string>

#include "pslam/slam/pslam.hpp"

namespace pslam {

void WriteHypothesesJson(const std::string& path, const PSlam& slam);

}  // namespace pslam
