// Maps the first 5800 scans of the ACES log with 10 particles at seed 9, through the two long
// corridors where the filter used to slide: driving north at x = 0 it ran 2.5 m ahead of the robot,
// driving west at y = -19 it fell 6 m behind (scans 5530-5690: 0.6 m of tracked motion against
// 3.7 m of odometry), and the map of that corridor ended doubled (0.211 m over the whole log).
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

constexpr int kSliceScans = 5800;  // about 1130 s of the log, past the end of the west corridor

TEST(RbpfAcesCorridor, TenParticlesDoNotSlideAlongTheLongCorridors) {
  PSLAM_REQUIRE_DATA(log, "aces/aces.clf");
  PSLAM_REQUIRE_DATA(relations_path, "aces/aces.relations");
  RbpfOptions options;
  options.particles = 10;
  options.seed = 9;
  options.threads = 1;
  options.loop_closure.enabled = true;
  Rbpf filter(options);
  const std::vector<StampedPose> trajectory = MapLogSlice(log.string(), filter, kSliceScans);
  const RpeResult rpe = ComputeRpe(trajectory, ReadRelations(relations_path.string()));
  ASSERT_GT(rpe.used, 800u) << "the slice should contain most of the relations";
  EXPECT_LT(rpe.trans_mean, 0.06);  // the published RBPF level on this log
  EXPECT_LT(rpe.trans_max, 1.0);    // no relation across a doubled corridor
  std::printf("ACES seed 9 slice RPE over %zu relations: %.4f m (max %.3f m), %.3f deg\n", rpe.used, rpe.trans_mean,
              rpe.trans_max, rpe.rot_mean_deg);
}

}  // namespace
}  // namespace pslam
