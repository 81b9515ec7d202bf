// Extend mode's handover from the localizer to the mapping filter waits for a tight cloud that
// has stayed localized over several updates, not the first scan that counts as localized.
#include <gtest/gtest.h>

#include "pslam/localize/mapping_handover.hpp"

namespace pslam {
namespace {

MclUpdate Step(bool localized, double position_std, double heading_std = 0.01, bool updated = true) {
  MclUpdate u;
  u.updated = updated;
  u.localized = localized;
  u.cluster.position_std = position_std;
  u.cluster.heading_std = heading_std;
  return u;
}

TEST(MappingHandoverTest, WaitsForATightCloudOverSeveralUpdates) {
  MappingHandover handover({.min_localized_updates = 3, .max_position_std = 0.08, .max_heading_std = 0.025});
  EXPECT_FALSE(handover.Ready(Step(true, 0.13)));  // localized, but a decimetre wide
  EXPECT_FALSE(handover.Ready(Step(true, 0.05)));
  EXPECT_FALSE(handover.Ready(Step(true, 0.05, 0.01, false)));  // scans between updates do not count
  EXPECT_FALSE(handover.Ready(Step(true, 0.05)));
  EXPECT_TRUE(handover.Ready(Step(true, 0.05)));
  EXPECT_TRUE(handover.Ready(Step(false, 0.5)));  // once handed over, for good
}

TEST(MappingHandoverTest, AStreakBrokenByDoubtStartsAgain) {
  MappingHandover handover({.min_localized_updates = 2, .max_position_std = 0.08, .max_heading_std = 0.025});
  EXPECT_FALSE(handover.Ready(Step(true, 0.05)));
  EXPECT_FALSE(handover.Ready(Step(false, 0.05)));         // a look-alike place was found
  EXPECT_FALSE(handover.Ready(Step(true, 0.05, 0.04)));    // heading too loose
  EXPECT_FALSE(handover.Ready(Step(true, 0.05)));
  EXPECT_TRUE(handover.Ready(Step(true, 0.05)));
}

}  // namespace
}  // namespace pslam
