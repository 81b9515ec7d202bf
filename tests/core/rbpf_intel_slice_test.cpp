// Maps the first minutes of the real Intel log and checks accuracy against the ground-truth
// relations that fall inside that slice, and that a fixed seed gives identical output.
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

constexpr int kSliceScans = 2000;  // the first 400 s of the log, with its first loops

std::vector<StampedPose> MapSlice(const std::string& log, int particles, std::uint64_t seed, int threads) {
  RbpfOptions options;
  options.particles = particles;
  options.seed = seed;
  options.threads = threads;
  Rbpf filter(options);
  return MapLogSlice(log, filter, kSliceScans);
}

TEST(RbpfIntelSlice, MeetsTheRelationErrorBoundInsideTheSlice) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  PSLAM_REQUIRE_DATA(relations_path, "intel/intel.relations");
  const std::vector<StampedPose> trajectory = MapSlice(log.string(), 10, 7, 0);
  ASSERT_EQ(trajectory.size(), static_cast<std::size_t>(kSliceScans));
  const RpeResult rpe = ComputeRpe(trajectory, ReadRelations(relations_path.string()));
  ASSERT_GT(rpe.used, 200u) << "the slice should contain a good share of the relations";
  EXPECT_LT(rpe.trans_mean, 0.04);
  EXPECT_LT(rpe.rot_mean_deg, 1.0);
  std::printf("slice RPE over %zu relations: %.4f m, %.3f deg\n", rpe.used, rpe.trans_mean, rpe.rot_mean_deg);
}

TEST(RbpfIntelSlice, SameSeedGivesIdenticalTrajectoriesWhateverTheThreadCount) {
  PSLAM_REQUIRE_DATA(log, "intel/intel.clf");
  const auto a = MapSlice(log.string(), 8, 3, 1);
  const auto b = MapSlice(log.string(), 8, 3, 2);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].pose.x, b[i].pose.x) << "scan " << i;
    ASSERT_EQ(a[i].pose.y, b[i].pose.y) << "scan " << i;
    ASSERT_EQ(a[i].pose.theta, b[i].pose.theta) << "scan " << i;
  }
}

}  // namespace
}  // namespace pslam
