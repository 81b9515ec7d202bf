#include "pslam/localize/mapping_handover.hpp"

namespace pslam {

bool MappingHandover::Ready(const MclUpdate& update) {
  if (ready_) return true;
  const bool tight = update.localized && update.cluster.position_std <= options_.max_position_std &&
                     update.cluster.heading_std <= options_.max_heading_std;
  if (!tight) {
    streak_ = 0;
  } else if (update.updated) {
    ready_ = ++streak_ >= options_.min_localized_updates;
  }
  return ready_;
}

}  // namespace pslam
