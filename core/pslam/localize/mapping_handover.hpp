#pragma once
// Extend mode hands the robot's pose from the localizer to the mapping filter, once. The mapping
// filter builds on that pose for good: every particle starts there and its first scans are mapped
// there, so a handover a decimetre off stays a decimetre off. Being localized (good enough to
// report a pose: MclOptions) is therefore not enough; the cloud must have stayed localized over a
// few updates, and be tight.
#include "pslam/localize/monte_carlo_localizer.hpp"

namespace pslam {

struct MappingHandoverOptions {
  int min_localized_updates = 5;   // localizer updates in a row, localized and tight
  double max_position_std = 0.08;  // m, the heaviest cluster's spread along its widest direction
  double max_heading_std = 0.025;  // rad
};

class MappingHandover {
 public:
  explicit MappingHandover(const MappingHandoverOptions& options = {}) : options_(options) {}
  // Takes the localizer's step at each scan; true once the pose may be handed over (and from then
  // on).
  bool Ready(const MclUpdate& update);
  bool ready() const { return ready_; }

 private:
  MappingHandoverOptions options_;
  int streak_ = 0;
  bool ready_ = false;
};

}  // namespace pslam
