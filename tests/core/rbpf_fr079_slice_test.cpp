// Maps the first 2200 scans of the FR079 log (a third building, a robot that backs up often, whose
// recorder logged backing up as driving on) with loop closure on, and checks the relation error
// inside that slice.
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

constexpr int kSliceScans = 2200;  // about 470 s: the west wing, its loops, and 60 of the log's reversals

TEST(RbpfFr079Slice, MapsTheWestWingWithinTheRelationErrorBound) {
  PSLAM_REQUIRE_DATA(log, "fr079/fr079.clf");
  PSLAM_REQUIRE_DATA(relations_path, "fr079/fr079.relations");
  RbpfOptions options;
  options.particles = 10;
  options.seed = 1;
  options.loop_closure.enabled = true;
  Rbpf filter(options);
  const std::vector<StampedPose> trajectory = MapLogSlice(log.string(), filter, kSliceScans);
  const RpeResult rpe = ComputeRpe(trajectory, ReadRelations(relations_path.string()));
  ASSERT_GT(rpe.used, 500u) << "the slice should contain a good share of the relations";
  EXPECT_LT(rpe.trans_mean, 0.06);  // the published RBPF level on this log
  EXPECT_LT(rpe.rot_mean_deg, 0.8);
  std::printf("FR079 slice RPE over %zu relations: %.4f m, %.3f deg; %d closures\n", rpe.used, rpe.trans_mean,
              rpe.rot_mean_deg, filter.loop_closer()->stats().closures);
}

}  // namespace
}  // namespace pslam
