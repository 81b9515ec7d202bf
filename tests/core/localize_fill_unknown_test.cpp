// Localizing where the map is missing: obstacles seen in cells the map never observed join the
// likelihood field (LikelihoodField::AddUnmappedObstacle, MclOptions::fill_unknown), so that a
// robot driving through a part the map lacks is not pulled onto the map's nearest walls.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pslam/experiment/localization_tour.hpp"
#include "pslam/io/map_io.hpp"
#include "pslam/localize/likelihood_field.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

// A 4 m x 4 m room mapped at 0.1 m: walls on its border, free inside; nothing known beyond.
OccupancyGrid MappedRoom() {
  OccupancyGrid map(0.1);
  for (int y = 0; y < 40; ++y) {
    for (int x = 0; x < 40; ++x) {
      const bool wall = x == 0 || y == 0 || x == 39 || y == 39;
      map.AddLogOdds(x, y, wall ? 3000 : -3000, -5000, 5000);
    }
  }
  return map;
}

TEST(LocalizeFillUnknownTest, ObstaclesJoinTheFieldOnlyWhereTheMapSawNothing) {
  const OccupancyGrid map = MappedRoom();
  LikelihoodFieldOptions options;
  options.max_extension = 10.0;
  LikelihoodField field(map, options);
  const float hit = std::log(static_cast<float>(options.z_hit + options.z_rand));

  // Free and occupied cells of the map stay as the map has them.
  EXPECT_FALSE(field.AddUnmappedObstacle({2.05, 2.05}));
  EXPECT_FALSE(field.AddUnmappedObstacle({0.05, 2.05}));
  EXPECT_LT(field.PointLogLikelihood({2.05, 2.05}), hit - 1.0f);

  // Off the map, within the table: scored far from any wall before, as a hit after.
  const Eigen::Vector2d outside(6.05, 2.05);
  EXPECT_FLOAT_EQ(field.PointLogLikelihood(outside), field.miss_log_likelihood());
  EXPECT_TRUE(field.AddUnmappedObstacle(outside));
  EXPECT_FALSE(field.AddUnmappedObstacle(outside));  // once
  EXPECT_NEAR(field.PointLogLikelihood(outside), hit, 1e-5);
  EXPECT_GT(field.PointLogLikelihood({6.25, 2.05}), field.PointLogLikelihood({6.55, 2.05}));

  // Beyond the table, the field grows; beyond the extension it refuses.
  const Eigen::Vector2d far(11.05, 2.05);
  EXPECT_TRUE(field.AddUnmappedObstacle(far));
  EXPECT_NEAR(field.PointLogLikelihood(far), hit, 1e-5);
  EXPECT_NEAR(field.PointLogLikelihood(outside), hit, 1e-5);  // kept through the growth
  EXPECT_FALSE(field.AddUnmappedObstacle({40.05, 2.05}));
  EXPECT_EQ(field.added_obstacles(), 2);
}

// The office with everything east of x = 20 m forgotten: the localizer starts in the known west
// and drives all over the building.
TEST(LocalizeFillUnknownTest, TracksThroughThePartTheMapLacks) {
  const std::string yaml = PSLAM_SOURCE_DIR "/core/worlds/office.yaml";
  const OccupancyGrid full = LoadMap(yaml);
  const World world = World::FromGrid(full);
  OccupancyGrid half = full;
  const CellBox known = full.KnownBounds();
  const int cut = static_cast<int>(20.0 / full.resolution());
  for (int y = known.min.y(); y <= known.max.y(); ++y) {
    for (int x = cut; x <= known.max.x(); ++x) half.Forget(x, y);
  }
  const Pose2D start = ReadStartPose(yaml).value();
  ASSERT_LT(start.x, 20.0);

  LocalizationTourOptions options;
  options.distance = 60.0;
  options.seed = 2;
  const LocalizationTourResult filled = RunLocalizationTour(world, half, start, options);
  options.mcl.fill_unknown = false;
  const LocalizationTourResult unfilled = RunLocalizationTour(world, half, start, options);

  int east = 0;
  for (const LocalizationSample& s : filled.samples) east += s.truth.x > 21.0;
  ASSERT_GT(east, static_cast<int>(filled.samples.size()) / 5) << "the tour hardly left the mapped part";
  const TrackingError with = MeasureTracking(filled.samples, 2.0);
  const TrackingError without = MeasureTracking(unfilled.samples, 2.0);
  // Without, the cloud is lost in the east (9.2 m off on average when written); with, it drifts
  // as mapping does where nothing closes a loop (0.19 m).
  EXPECT_LT(with.mean_position, 0.3);
  EXPECT_LT(with.mean_position, 0.1 * without.mean_position);
}

}  // namespace
}  // namespace pslam
