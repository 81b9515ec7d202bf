// Localizing where the map is missing: obstacles seen in cells the map never observed join the
// likelihood field (LikelihoodField::AddUnmappedObstacle, MclOptions::fill_unknown), so that a
// robot driving through a part the map lacks is not pulled onto the map's nearest walls. (That a
// kidnapped robot draws no walls where it is not is LocalizeMclTest.RecoversAfterTheRobotIsCarriedElsewhere.)
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
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
  const LikelihoodFieldOptions options;
  LikelihoodField field(map, options);
  const float hit = std::log(static_cast<float>(options.z_hit + options.z_rand));

  // Free and occupied cells of the map stay as the map has them.
  EXPECT_FALSE(field.AddUnmappedObstacle({2.05, 2.05}));
  EXPECT_FALSE(field.AddUnmappedObstacle({0.05, 2.05}));
  EXPECT_LT(field.PointLogLikelihood({2.05, 2.05}), hit - 1.0f);

  // Beyond the map's walls, within max_distance of its bounds: scored far from any wall before,
  // as a hit after.
  const Eigen::Vector2d outside(5.55, 2.05);
  EXPECT_LT(field.PointLogLikelihood(outside), hit - 1.0f);
  EXPECT_TRUE(field.AddUnmappedObstacle(outside));
  EXPECT_NEAR(field.PointLogLikelihood(outside), hit, 1e-5);
  EXPECT_GT(field.PointLogLikelihood({5.75, 2.05}), field.PointLogLikelihood({5.05, 2.05}));
  // Not twice, nor next to it (walls stay thin), nor off the table.
  EXPECT_FALSE(field.AddUnmappedObstacle(outside));
  EXPECT_FALSE(field.AddUnmappedObstacle({5.65, 2.05}));
  EXPECT_TRUE(field.AddUnmappedObstacle({5.55, 2.35}));
  EXPECT_FALSE(field.AddUnmappedObstacle({8.05, 2.05}));
  EXPECT_EQ(field.added_obstacles(), 2);

  // What the map can check: cells it observed, and beams through its walls.
  EXPECT_EQ(field.ExplainedByMap({0.12, 2.05}), std::optional<bool>(true));
  EXPECT_EQ(field.ExplainedByMap({2.05, 2.05}), std::optional<bool>(false));
  EXPECT_FALSE(field.ExplainedByMap({5.05, 2.05}).has_value());
  EXPECT_TRUE(field.BeamBlocked({2.05, 2.05}, {5.55, 3.05}));    // out through the east wall
  EXPECT_FALSE(field.BeamBlocked({2.05, 2.05}, {3.05, 3.05}));   // inside the room
  EXPECT_FALSE(field.BeamBlocked({2.05, 2.05}, {3.95, 2.05}));   // onto the wall's face
}

// The office with a band of it forgotten (20 m <= x < 34 m, its whole height): the localizer
// starts in the known west and drives all over the building.
TEST(LocalizeFillUnknownTest, TracksThroughThePartTheMapLacks) {
  const std::string yaml = PSLAM_SOURCE_DIR "/core/worlds/office.yaml";
  const OccupancyGrid full = LoadMap(yaml);
  const World world = World::FromGrid(full);
  OccupancyGrid partial = full;
  const CellBox known = full.KnownBounds();
  const int cut = static_cast<int>(20.0 / full.resolution());
  for (int y = known.min.y(); y <= known.max.y(); ++y) {
    for (int x = cut; x < static_cast<int>(34.0 / full.resolution()); ++x) partial.Forget(x, y);
  }
  const Pose2D start = ReadStartPose(yaml).value();
  ASSERT_LT(start.x, 20.0);

  LocalizationTourOptions options;
  options.distance = 60.0;
  options.seed = 2;
  const LocalizationTourResult filled = RunLocalizationTour(world, partial, start, options);
  options.mcl.fill_unknown = false;
  const LocalizationTourResult unfilled = RunLocalizationTour(world, partial, start, options);

  int in_band = 0;
  for (const LocalizationSample& s : filled.samples) in_band += s.truth.x > 21.0 && s.truth.x < 33.0;
  ASSERT_GT(in_band, static_cast<int>(filled.samples.size()) / 5) << "the tour hardly left the mapped part";
  const TrackingError with = MeasureTracking(filled.samples, 2.0);
  const TrackingError without = MeasureTracking(unfilled.samples, 2.0);
  // Without, the cloud is lost (11.8 m off on average when written); with, 0.051 m.
  EXPECT_LT(with.mean_position, 0.15);
  EXPECT_LT(with.mean_position, 0.1 * without.mean_position);
}

}  // namespace
}  // namespace pslam
