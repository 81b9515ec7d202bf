// Global localization by place recognition on the shipped worlds: the square maze is the same
// turned by 90 degrees about its centre, so a search there must name the robot's place and its
// turned twin as rivals, and Monte Carlo localization must never claim one of them; the irregular
// room has no look-alike place, so a few metres recognize it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "pslam/experiment/localization_tour.hpp"
#include "pslam/io/map_io.hpp"
#include "pslam/localize/place_recognizer.hpp"
#include "pslam/sensor/scan_points.hpp"
#include "pslam/sim/laser_model.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

constexpr double kPi = std::numbers::pi;

std::string WorldPath(const std::string& name) {
  std::string path = PSLAM_SOURCE_DIR;
  path.append("/core/worlds/").append(name).append(".yaml");
  return path;
}

// Scans every 0.2 m along a straight drive, with exact odometry.
void Drive(PlaceRecognizer& places, const World& world, const Pose2D& from, double length) {
  std::mt19937_64 rng(7);
  for (double s = 0.0; s <= length + 1e-9; s += 0.2) {
    const Pose2D pose = from * Pose2D(s, 0.0, 0.0);
    const LaserScan scan = SimulateScan(world, pose, LaserOptions{}, rng);
    places.Add(ToScanPoints(scan, ScanPointsOptions{}).hits, pose);
  }
}

// The pose turned by k quarter turns about 'centre'.
Pose2D Turned(const Pose2D& p, const Eigen::Vector2d& centre, int k) {
  const Eigen::Vector2d d = Eigen::Rotation2Dd(k * kPi / 2.0) * (p.translation() - centre) + centre;
  return {d.x(), d.y(), p.theta + k * kPi / 2.0};
}

// Which quarter turn of 'truth' about 'centre' the pose is, within 0.25 m and 0.1 rad; -1 if none.
int QuarterTurnOf(const Pose2D& pose, const Pose2D& truth, const Eigen::Vector2d& centre) {
  for (int k = 0; k < 4; ++k) {
    const Pose2D image = Turned(truth, centre, k);
    if ((image.translation() - pose.translation()).norm() < 0.25 && std::abs(NormalizeAngle(image.theta - pose.theta)) < 0.1) return k;
  }
  return -1;
}

TEST(PlaceRecognizerTest, NamesTheTurnedTwinInTheSymmetricMaze) {
  const OccupancyGrid map = LoadMap(WorldPath("maze"));
  const World world = World::FromGrid(map);
  PlaceRecognizer places(map, PlaceRecognitionOptions{});
  EXPECT_FALSE(places.SearchDue());
  // Westwards along the south corridor into the corner: the corner in sight rules out the
  // corridor's own repetition, and leaves the four corners.
  const Pose2D start(6.0, 1.1, kPi);
  Drive(places, world, start, 4.4);
  ASSERT_TRUE(places.SearchDue());
  const PlaceMatch match = places.Search();
  EXPECT_TRUE(places.searched());
  EXPECT_FALSE(places.SearchDue());
  ASSERT_EQ(match.outcome, PlaceMatch::Outcome::kAmbiguous);
  const Pose2D end = start * Pose2D(4.4, 0.0, 0.0);
  const Eigen::Vector2d centre(12.5, 12.5);  // the maze's interior spans 0..25 m
  const int best = QuarterTurnOf(match.pose, end, centre), rival = QuarterTurnOf(match.rival, end, centre);
  EXPECT_NE(best, -1) << match.pose.x << ", " << match.pose.y << ", " << match.pose.theta;
  EXPECT_NE(rival, -1) << match.rival.x << ", " << match.rival.y << ", " << match.rival.theta;
  EXPECT_NE(best, rival);
  EXPECT_GT(match.score, 0.7);
  EXPECT_NEAR(match.rival_score / match.score, 1.0, 0.02);
}

TEST(PlaceRecognizerTest, RecognizesTheIrregularRoomAtOnce) {
  const OccupancyGrid map = LoadMap(WorldPath("irregular"));
  const World world = World::FromGrid(map);
  PlaceRecognizer places(map, PlaceRecognitionOptions{});
  const Pose2D start = ReadStartPose(WorldPath("irregular")).value();
  Drive(places, world, start, 1.2);
  const PlaceMatch match = places.Search();
  ASSERT_EQ(match.outcome, PlaceMatch::Outcome::kUnique);
  const Pose2D end = start * Pose2D(1.2, 0.0, 0.0);
  EXPECT_LT((match.pose.translation() - end.translation()).norm(), 0.15);
  EXPECT_LT(std::abs(NormalizeAngle(match.pose.theta - end.theta)), 0.05);

  // Forgotten after a reset: nothing to search until the robot has moved again.
  places.Reset();
  EXPECT_FALSE(places.searched());
  EXPECT_FALSE(places.SearchDue());
  EXPECT_EQ(places.Search().outcome, PlaceMatch::Outcome::kNone);
}

TEST(PlaceRecognizerTest, LocalizerNeverClaimsATwinOfTheMaze) {
  const OccupancyGrid map = LoadMap(WorldPath("maze"));
  const World world = World::FromGrid(map);
  LocalizationTourOptions options;
  options.global = true;
  options.distance = 25.0;
  const LocalizationTourResult run = RunLocalizationTour(world, map, ReadStartPose(WorldPath("maze")).value(), options);
  ASSERT_GE(run.distance, 25.0);
  int localized = 0;
  for (const LocalizationSample& s : run.samples) localized += s.localized;
  EXPECT_EQ(localized, 0);

  // Without the search, the particles settle on one of the four places and say so.
  options.mcl.place.enabled = false;
  const LocalizationTourResult plain = RunLocalizationTour(world, map, ReadStartPose(WorldPath("maze")).value(), options);
  int claimed = 0;
  for (const LocalizationSample& s : plain.samples) claimed += s.localized;
  EXPECT_GT(claimed, 0);
}

}  // namespace
}  // namespace pslam
