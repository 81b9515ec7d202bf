// Maps the first 3000 scans of the ACES log (a second building, another robot) with loop closure
// on, and checks the relation error inside that slice.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "pslam/eval/relative_pose_error.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/io/carmen_reader.hpp"
#include "testing/shared_data.hpp"

namespace pslam {
namespace {

constexpr int kSliceScans = 3000;  // about 9 minutes of the log, around its first loops

TEST(RbpfAcesSlice, ClosesLoopsAndMeetsTheRelationErrorBoundInsideTheSlice) {
  PSLAM_REQUIRE_DATA(log, "aces/aces.clf");
  PSLAM_REQUIRE_DATA(relations_path, "aces/aces.relations");
  CarmenReader reader(log.string());
  ScanStream scans(reader);
  RbpfOptions options;
  options.particles = 10;
  options.seed = 1;
  options.loop_closure.enabled = true;
  Rbpf filter(options);
  std::vector<std::string> stamps;
  while (auto scan = scans.Next()) {
    if (static_cast<int>(stamps.size()) == kSliceScans) break;
    stamps.push_back(scan->timestamp_text);
    filter.AddScan(*scan);
  }
  filter.FlushLoopClosure();
  ASSERT_NE(filter.loop_closer(), nullptr);
  EXPECT_GT(filter.loop_closer()->stats().closures, 0);
  const std::vector<Pose2D> poses = filter.Trajectory();
  std::vector<StampedPose> trajectory;
  for (std::size_t i = 0; i < poses.size(); ++i) trajectory.push_back({stamps[i], 0.0, poses[i]});
  const RpeResult rpe = ComputeRpe(trajectory, ReadRelations(relations_path.string()));
  ASSERT_GT(rpe.used, 400u) << "the slice should contain a good share of the relations";
  EXPECT_LT(rpe.trans_mean, 0.05);
  EXPECT_LT(rpe.rot_mean_deg, 0.6);
  std::printf("ACES slice RPE over %zu relations: %.4f m, %.3f deg; %d closures\n", rpe.used, rpe.trans_mean,
              rpe.rot_mean_deg, filter.loop_closer()->stats().closures);
}

}  // namespace
}  // namespace pslam
