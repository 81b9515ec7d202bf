#include "pslam/eval/relative_pose_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include "pslam/eval/trajectory_io.hpp"
#include "testing/shared_data.hpp"

namespace pslam {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

std::string Stamp(int i) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6f", 976052857.337530 + 0.25 * i);
  return text;
}

// A wiggly ground-truth path: steps of varying length and turn.
std::vector<Pose2D> TruePath(int n) {
  std::vector<Pose2D> path{Pose2D(1.0, -2.0, 0.3)};
  for (int i = 1; i < n; ++i) path.push_back(path.back() * Pose2D(0.2 + 0.01 * i, 0.05 * std::sin(i), 0.1 * std::cos(i)));
  return path;
}

std::vector<Relation> ConsecutiveRelations(const std::vector<Pose2D>& path) {
  std::vector<Relation> relations;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    relations.push_back({Stamp(static_cast<int>(i)), Stamp(static_cast<int>(i + 1)), Between(path[i], path[i + 1])});
  }
  return relations;
}

std::vector<StampedPose> Stamped(const std::vector<Pose2D>& poses) {
  std::vector<StampedPose> out;
  for (std::size_t i = 0; i < poses.size(); ++i) out.push_back({Stamp(static_cast<int>(i)), 0.0, poses[i]});
  return out;
}

TEST(RelativePoseError, PerfectTrajectoryInAnyWorldFrameHasZeroError) {
  const std::vector<Pose2D> truth = TruePath(30);
  std::vector<Pose2D> moved;
  const Pose2D world_shift(5.0, -3.0, 1.2);  // the metric must not care where the map frame is
  for (const Pose2D& p : truth) moved.push_back(world_shift * p);
  const RpeResult r = ComputeRpe(Stamped(moved), ConsecutiveRelations(truth));
  EXPECT_EQ(r.used, 29u);
  EXPECT_EQ(r.missing, 0u);
  EXPECT_NEAR(r.trans_mean, 0.0, 1e-9);
  EXPECT_NEAR(r.rot_max_deg, 0.0, 1e-9);
}

TEST(RelativePoseError, KnownErrorOnEveryOtherStepGivesExactStatistics) {
  // The estimate takes each true step, and on even steps adds P: then Between(est_i, est_i+1) =
  // delta_i * P, so the error of those relations is exactly P, and 0 for the others.
  const Pose2D perturbation(0.03, 0.04, 0.02);  // 0.05 m, 0.02 rad
  const std::vector<Pose2D> truth = TruePath(21);
  std::vector<Pose2D> estimate{Pose2D(-7.0, 2.0, -2.0)};
  for (std::size_t i = 0; i + 1 < truth.size(); ++i) {
    const Pose2D step = Between(truth[i], truth[i + 1]);
    estimate.push_back(estimate.back() * (i % 2 == 0 ? step * perturbation : step));
  }
  const RpeResult r = ComputeRpe(Stamped(estimate), ConsecutiveRelations(truth));
  ASSERT_EQ(r.used, 20u);
  const double rot_deg = 0.02 * kDegPerRad;
  // Half the errors are e, half 0: mean e/2, population std e/2.
  EXPECT_NEAR(r.trans_mean, 0.025, 1e-9);
  EXPECT_NEAR(r.trans_std, 0.025, 1e-9);
  EXPECT_NEAR(r.trans_max, 0.05, 1e-9);
  EXPECT_NEAR(r.rot_mean_deg, rot_deg / 2, 1e-7);
  EXPECT_NEAR(r.rot_std_deg, rot_deg / 2, 1e-7);
  EXPECT_NEAR(r.rot_max_deg, rot_deg, 1e-7);
  EXPECT_NEAR(r.trans2_mean, 0.0025 / 2, 1e-10);
  EXPECT_NEAR(r.trans2_std, 0.0025 / 2, 1e-10);
  EXPECT_NEAR(r.rot2_mean_deg2, rot_deg * rot_deg / 2, 1e-6);
  EXPECT_NEAR(r.rot2_std_deg2, rot_deg * rot_deg / 2, 1e-6);
}

TEST(RelativePoseError, RelationIsTheSecondPoseInTheFrameOfTheFirst) {
  // Facing +y at the origin, then 1 m further along +y: 1 m straight ahead in the robot frame.
  const std::vector<StampedPose> trajectory = {{"1.000000", 1.0, Pose2D(0, 0, std::numbers::pi / 2)},
                                               {"2.000000", 2.0, Pose2D(0, 1, std::numbers::pi / 2)}};
  const RpeResult right = ComputeRpe(trajectory, {{"1.000000", "2.000000", Pose2D(1, 0, 0)}});
  EXPECT_NEAR(right.trans_mean, 0.0, 1e-12);
  // The world-frame difference, or the reversed relation, is wrong by a known amount.
  const RpeResult world = ComputeRpe(trajectory, {{"1.000000", "2.000000", Pose2D(0, 1, 0)}});
  EXPECT_NEAR(world.trans_mean, std::sqrt(2.0), 1e-12);
  const RpeResult reversed = ComputeRpe(trajectory, {{"1.000000", "2.000000", Pose2D(-1, 0, 0)}});
  EXPECT_NEAR(reversed.trans_mean, 2.0, 1e-12);
  // Rotation error is the wrapped angle: 350 deg off is 10 deg off.
  const RpeResult turned = ComputeRpe(trajectory, {{"1.000000", "2.000000", Pose2D(1, 0, 350.0 / kDegPerRad)}});
  EXPECT_NEAR(turned.rot_mean_deg, 10.0, 1e-9);
}

TEST(RelativePoseError, MissingStampsAreCountedNotUsed) {
  const std::vector<Pose2D> truth = TruePath(5);
  std::vector<Relation> relations = ConsecutiveRelations(truth);
  relations.push_back({Stamp(0), "123.456789", Pose2D()});
  relations.push_back({"5.5", Stamp(1), Pose2D()});
  const RpeResult r = ComputeRpe(Stamped(truth), relations);
  EXPECT_EQ(r.used, 4u);
  EXPECT_EQ(r.missing, 2u);
  EXPECT_NEAR(r.trans_mean, 0.0, 1e-9);

  const RpeResult none = ComputeRpe({}, relations);
  EXPECT_EQ(none.used, 0u);
  EXPECT_EQ(none.missing, 6u);
  EXPECT_EQ(none.trans_mean, 0.0);
}

TEST(RelativePoseError, StampsMatchByTimeWithinTheTolerance) {
  const std::vector<StampedPose> trajectory = {{"976052857.337530", 0.0, Pose2D(0, 0, 0)},
                                               {"976052858.000000", 0.0, Pose2D(2, 0, 0)}};
  const std::vector<Relation> relations = {{"976052857.33753", "976052858", Pose2D(1.5, 0, 0)},
                                           {"976052857.33755", "976052858", Pose2D(1.5, 0, 0)}};
  const RpeResult r = ComputeRpe(trajectory, relations);  // 20 us is well inside the default 1 ms
  EXPECT_EQ(r.used, 2u);
  EXPECT_EQ(r.missing, 0u);
  EXPECT_NEAR(r.trans_mean, 0.5, 1e-12);
  EXPECT_NEAR(r.max_stamp_offset_s, 20e-6, 2e-7);  // doubles near 1e9 s resolve 1.2e-7 s
  const RpeResult tight = ComputeRpe(trajectory, relations, 1e-6);
  EXPECT_EQ(tight.used, 1u);
  EXPECT_EQ(tight.missing, 1u);
  EXPECT_EQ(tight.stamp_tolerance_s, 1e-6);
}

TEST(RelativePoseError, RelationsWithFewerDecimalsThanTheLogMatch) {
  // Intel log scans 0.9 ms apart; rounded to 5 decimals their stamps move by 1-3 us.
  const std::vector<StampedPose> trajectory = {{"976052888.424429", 0.0, Pose2D(0, 0, 0)},
                                               {"976052888.425469", 0.0, Pose2D(1, 0, 0)},
                                               {"976052888.426363", 0.0, Pose2D(3, 0, 0)}};
  const RpeResult r = ComputeRpe(trajectory, {{"976052888.42443", "976052888.42547", Pose2D(1, 0, 0)},
                                              {"976052888.42547", "976052888.42636", Pose2D(2, 0, 0)}});
  EXPECT_EQ(r.used, 2u);
  EXPECT_EQ(r.missing, 0u);
  EXPECT_NEAR(r.trans_max, 0.0, 1e-12);  // each stamp took its own scan, not a neighbour within 1 ms
  EXPECT_LT(r.max_stamp_offset_s, 5e-6);
}

TEST(RelativePoseError, NearestStampWinsAndRepeatsTakeTheFirst) {
  const std::vector<StampedPose> trajectory = {{"10.0000", 0.0, Pose2D(0, 0, 0)},  {"10.0008", 0.0, Pose2D(1, 0, 0)},
                                               {"10.0008", 0.0, Pose2D(9, 0, 0)},  {"", 20.0, Pose2D(5, 0, 0)}};
  const RpeResult r = ComputeRpe(trajectory, {{"10.0007", "20.0003", Pose2D(4, 0, 0)},  // 10.0008, first of two
                                              {"10.0003", "20", Pose2D(5, 0, 0)}});     // 10.0000; time without text
  EXPECT_EQ(r.used, 2u);
  EXPECT_NEAR(r.trans_max, 0.0, 1e-12);
}

TEST(RelativePoseError, TooManyMissingRelationsAreAnError) {
  const std::vector<Pose2D> truth = TruePath(21);
  std::vector<Relation> relations = ConsecutiveRelations(truth);  // 20 that match
  relations.push_back({Stamp(0), "5.25", Pose2D()});
  const RpeResult one = ComputeRpe(Stamped(truth), relations);
  EXPECT_EQ(one.missing, 1u);
  EXPECT_EQ(TooManyMissing(one, 5.0), std::nullopt);  // 1 of 21 = 4.8 %
  relations.push_back({"7.5", Stamp(1), Pose2D()});
  const RpeResult two = ComputeRpe(Stamped(truth), relations);
  EXPECT_EQ(two.missing, 2u);
  const auto problem = TooManyMissing(two, 5.0);  // 2 of 22 = 9.1 %
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("2 of 22 relations (9.1 %)"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("0.001 s"), std::string::npos) << *problem;
  EXPECT_EQ(TooManyMissing(two, 10.0), std::nullopt);
  // Nothing matched, or nothing to match, is an error whatever the limit.
  EXPECT_TRUE(TooManyMissing(ComputeRpe({}, relations), 100.0).has_value());
  EXPECT_TRUE(TooManyMissing(ComputeRpe(Stamped(truth), {}), 100.0).has_value());
}

TEST(RelativePoseError, ReadsRelationsAndReportsBadLines) {
  std::istringstream in(
      "976052905.167303 976052911.885496 -0.056990 -0.128430 0.000000 0.000000 0.000000 -1.682210\n"
      "\n"
      "1 2 3 4 5 6 7 0.5\n");
  const std::vector<Relation> relations = ReadRelations(in, "rel.txt");
  ASSERT_EQ(relations.size(), 2u);
  EXPECT_EQ(relations[0].stamp1, "976052905.167303");
  EXPECT_EQ(relations[0].stamp2, "976052911.885496");
  EXPECT_DOUBLE_EQ(relations[0].delta.x, -0.056990);
  EXPECT_DOUBLE_EQ(relations[0].delta.y, -0.128430);
  EXPECT_DOUBLE_EQ(relations[0].delta.theta, -1.682210);
  EXPECT_DOUBLE_EQ(relations[1].delta.theta, 0.5);  // yaw is the 8th field, not z/roll/pitch

  std::istringstream short_line("1 2 3 4 5 6 7 8\n1 2 3\n");
  try {
    ReadRelations(short_line, "rel.txt");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("rel.txt:2:"), std::string::npos) << e.what();
  }
  std::istringstream bad_number("1 2 3 4 5 6 7 yaw\n");
  EXPECT_THROW(ReadRelations(bad_number, "rel.txt"), std::runtime_error);
  EXPECT_THROW(ReadRelations("/nonexistent/rel.txt"), std::runtime_error);
}

TEST(TrajectoryIo, WritesAndReadsStampsVerbatim) {
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / ("pslam_traj_" + std::to_string(getpid()) + ".txt")).string();
  const std::vector<StampedPose> poses = {{"976052857.337530", 0.0, Pose2D(1.25, -2.5, 0.125)},
                                          {"", 12.5, Pose2D(-0.0000004, 3.0, -3.0)}};
  WriteTrajectory(path, poses);
  std::ostringstream text;
  WriteTrajectory(text, poses);
  EXPECT_EQ(text.str(), "976052857.337530 1.250000 -2.500000 0.125000\n12.500000 -0.000000 3.000000 -3.000000\n");

  const std::vector<StampedPose> read = ReadTrajectory(path);
  std::filesystem::remove(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].stamp, "976052857.337530");
  EXPECT_DOUBLE_EQ(read[0].time, 976052857.337530);
  EXPECT_DOUBLE_EQ(read[0].pose.x, 1.25);
  EXPECT_DOUBLE_EQ(read[0].pose.theta, 0.125);
  EXPECT_EQ(read[1].stamp, "12.500000");

  std::istringstream bad("# header\n1.0 2 3 4\n2.0 2 3\n");
  try {
    ReadTrajectory(bad, "traj.txt");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("traj.txt:3:"), std::string::npos) << e.what();
  }
  std::istringstream bad_stamp("1.0x 2 3 4\n");
  EXPECT_THROW(ReadTrajectory(bad_stamp, "traj.txt"), std::runtime_error);
}

TEST(RelativePoseError, ReadsTheIntelRelations) {
  PSLAM_REQUIRE_DATA(path, "intel/intel.relations");
  const std::vector<Relation> relations = ReadRelations(path.string());
  ASSERT_EQ(relations.size(), 2984u);
  EXPECT_EQ(relations[0].stamp1, "976052905.167303");
  EXPECT_DOUBLE_EQ(relations[0].delta.theta, -1.682210);
}

TEST(RelativePoseError, IntelRelationsRoundedToFiveDecimalsAllMatch) {
  PSLAM_REQUIRE_DATA(path, "intel/intel.relations");
  const std::vector<Relation> relations = ReadRelations(path.string());
  // A trajectory at the relations' own (log) stamps, each pose distinct, and the relations
  // rewritten with 5 decimals as another tool might have saved them.
  std::vector<StampedPose> trajectory;
  std::vector<Relation> rounded;
  auto round5 = [](const std::string& stamp) {
    char text[32];
    std::snprintf(text, sizeof text, "%.5f", *ParseStampSeconds(stamp));
    return std::string(text);
  };
  for (const Relation& r : relations) {
    for (const std::string& stamp : {r.stamp1, r.stamp2}) {
      trajectory.push_back({stamp, 0.0, Pose2D(static_cast<double>(trajectory.size()), 0.0, 0.0)});
    }
    rounded.push_back({round5(r.stamp1), round5(r.stamp2), r.delta});
  }
  const RpeResult exact = ComputeRpe(trajectory, relations);
  ASSERT_EQ(exact.used, 2984u);
  const RpeResult r = ComputeRpe(trajectory, rounded);
  EXPECT_EQ(r.used, 2984u);
  EXPECT_EQ(r.missing, 0u);
  EXPECT_LE(r.max_stamp_offset_s, 5.1e-6);
  EXPECT_EQ(r.trans_mean, exact.trans_mean);  // the same poses were found
}

}  // namespace
}  // namespace pslam
