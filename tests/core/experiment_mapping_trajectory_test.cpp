// A built map's own poses carry a true pose to where the map has that place.
#include "pslam/experiment/mapping_trajectory.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "testing/temp_dir.hpp"

namespace pslam {
namespace {

// A corridor mapped along x: the map is right up to x = 10 m, and from there on it has everything
// 0.3 m further along and turned by 0.02 rad (a bend).
std::vector<MappedPose> BentCorridor() {
  std::vector<MappedPose> poses;
  const Pose2D bend(0.3, 0.0, 0.02);
  for (double x = 0.0; x <= 20.0; x += 0.25) {
    const Pose2D truth(x, 1.0, 0.0);
    poses.push_back({truth, x < 10.0 ? truth : bend * truth});
  }
  return poses;
}

TEST(MappingTrajectoryTest, CarriesATruePoseToWhereTheMapHasThePlace) {
  const MapLocalFrame frame(BentCorridor());
  const std::optional<Pose2D> straight = frame.ToMap(Pose2D(5.1, 1.2, 1.0));
  ASSERT_TRUE(straight);
  EXPECT_NEAR(straight->x, 5.1, 1e-9);
  EXPECT_NEAR(straight->y, 1.2, 1e-9);
  EXPECT_NEAR(straight->theta, 1.0, 1e-9);

  const Pose2D truth(15.1, 1.2, 1.0);
  const std::optional<Pose2D> bent = frame.ToMap(truth);
  ASSERT_TRUE(bent);
  const Pose2D expected = Pose2D(0.3, 0.0, 0.02) * truth;
  EXPECT_NEAR(bent->x, expected.x, 1e-9);
  EXPECT_NEAR(bent->y, expected.y, 1e-9);
  EXPECT_NEAR(bent->theta, expected.theta, 1e-9);
}

TEST(MappingTrajectoryTest, NothingWhereTheMappingRunNeverPassed) {
  const MapLocalFrame frame(BentCorridor());
  EXPECT_FALSE(frame.ToMap(Pose2D(5.0, 2.5, 0.0)));
  EXPECT_TRUE(frame.ToMap(Pose2D(5.0, 2.5, 0.0), 2.0));
  EXPECT_FALSE(frame.ToMap(Pose2D(-30.0, 1.0, 0.0), 5.0));
  EXPECT_FALSE(MapLocalFrame({}).ToMap(Pose2D()));
}

TEST(MappingTrajectoryTest, SavedBesideTheMapAndReadBack) {
  const testing::TempDir dir("mapping_trajectory");
  EXPECT_EQ(MappingTrajectoryPath("a/office.yaml"), "a/office_trajectory.txt");
  EXPECT_EQ(MappingTrajectoryPath("a/office"), "a/office_trajectory.txt");
  const std::string path = MappingTrajectoryPath((dir.path() / "office.yaml").string());
  SaveMappingTrajectory(path, BentCorridor());
  const std::vector<MappedPose> back = LoadMappingTrajectory(path);
  ASSERT_EQ(back.size(), BentCorridor().size());
  EXPECT_NEAR(back.back().in_map.x, BentCorridor().back().in_map.x, 1e-7);
  EXPECT_NEAR(back.back().in_map.theta, 0.02, 1e-7);
}

TEST(MappingTrajectoryTest, AMalformedLineIsAnErrorNamingIt) {
  const testing::TempDir dir("mapping_trajectory");
  const std::string path = (dir.path() / "bad_trajectory.txt").string();
  std::ofstream(path) << "1 2 3 4 5 6\n1 2 three 4 5 6\n";
  try {
    LoadMappingTrajectory(path);
    FAIL() << "a malformed line was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad_trajectory.txt:2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LoadMappingTrajectory((dir.path() / "missing.txt").string()), std::runtime_error);
}

}  // namespace
}  // namespace pslam
