// `pslam eval --map --reference` (the real binary): a map that is right but sits off its floor plan
// scores low as it lies and high once laid onto it; maps of another resolution are refused plainly.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>

#include "pslam/grid/grid_transform.hpp"
#include "pslam/io/map_io.hpp"
#include "testing/cli_scratch.hpp"

namespace pslam {
namespace {

const std::string kFloorPlan = std::string(PSLAM_SOURCE_DIR) + "/core/worlds/irregular.yaml";

class EvalMapCliTest : public ::testing::Test {
 protected:
  // Exit status of `pslam eval ARGS`; stdout in out_.
  int Run(const std::string& args) {
    const int status = scratch_.Run("eval", args);
    out_ = scratch_.Read("out.txt");
    return status;
  }
  // A number of the one-line JSON object: "name": value.
  double Field(const std::string& name) {
    std::smatch m;
    if (!std::regex_search(out_, m, std::regex("\"" + name + "\": ([-0-9.eE+]+)"))) {
      ADD_FAILURE() << name << " missing from " << out_;
      return 0.0;
    }
    return std::stod(m[1]);
  }

  pslam::testing::CliScratch scratch_{"eval-map"};
  std::string out_;
};

TEST_F(EvalMapCliTest, AMapThatSitsOffItsFloorPlanIsRightOnceLaidOntoIt) {
  const OccupancyGrid plan = LoadMap(kFloorPlan);
  SaveMap(TransformGrid(plan, Pose2D{0.3, -0.25, 0.0}), scratch_.Path("off"));
  ASSERT_EQ(Run("--json --map " + scratch_.Path("off.yaml") + " --reference " + kFloorPlan), 0) << out_;
  EXPECT_LT(Field("psi"), 0.7);
  EXPECT_GT(Field("psi_laid_onto"), 0.9);
  EXPECT_NEAR(Field("laid_onto_shift_m"), std::hypot(0.3, 0.25), 0.05);
  EXPECT_GT(Field("kl"), 0.0);

  ASSERT_EQ(Run("--map " + kFloorPlan + " --reference " + kFloorPlan), 0);
  EXPECT_NE(out_.find("Psi of the map's walls against the reference's: 1.000 as it lies, 1.000 laid onto it"),
            std::string::npos)
      << out_;
}

TEST_F(EvalMapCliTest, MapsOfAnotherResolutionAreRefusedPlainly) {
  OccupancyGrid coarse(0.1);
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) coarse.MutableAt(x, y) = (x == 0 || y == 0) ? 3000 : -2000;
  }
  SaveMap(coarse, scratch_.Path("coarse"));
  EXPECT_EQ(Run("--map " + scratch_.Path("coarse.yaml") + " --reference " + kFloorPlan), 1);
  const std::string err = scratch_.Read("err.txt");
  EXPECT_NE(err.find("map resolutions differ: reference 0.05 m, evaluated 0.1 m"), std::string::npos) << err;
}

}  // namespace
}  // namespace pslam
