// Maps the first 3000 scans of the ACES log (a second building, another robot) with loop closure
// on, and checks the relation error inside that slice.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "pslam/eval/relative_pose_error.hpp"
#include "pslam/filter/rbpf.hpp"
#include "testing/log_slice.hpp"
#include "testing/shared_data.hpp"

namespace pslam {
namespace {

constexpr int kSliceScans = 3000;  // about 9 minutes of the log, around its first loops

TEST(RbpfAcesSlice, ClosesLoopsAndMeetsTheRelationErrorBoundInsideTheSlice) {
  PSLAM_REQUIRE_DATA(log, "aces/aces.clf");
  PSLAM_REQUIRE_DATA(relations_path, "aces/aces.relations");
  RbpfOptions options;
  options.particles = 10;
  options.seed = 1;
  options.loop_closure.enabled = true;
  Rbpf filter(options);
  const std::vector<StampedPose> trajectory = MapLogSlice(log.string(), filter, kSliceScans);
  ASSERT_NE(filter.loop_closer(), nullptr);
  EXPECT_GT(filter.loop_closer()->stats().closures, 0);
  const RpeResult rpe = ComputeRpe(trajectory, ReadRelations(relations_path.string()));
  ASSERT_GT(rpe.used, 400u) << "the slice should contain a good share of the relations";
  EXPECT_LT(rpe.trans_mean, 0.05);
  EXPECT_LT(rpe.rot_mean_deg, 0.6);
  std::printf("ACES slice RPE over %zu relations: %.4f m, %.3f deg; %d closures\n", rpe.used, rpe.trans_mean,
              rpe.rot_mean_deg, filter.loop_closer()->stats().closures);
}

}  // namespace
}  // namespace pslam
