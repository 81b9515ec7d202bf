// `pslam eval --map --reference` (the real binary): a map that is right but sits off its floor plan
// scores low as it lies and high once laid onto it; maps of another resolution are refused plainly.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "pslam/grid/grid_transform.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

namespace fs = std::filesystem;

const std::string kFloorPlan = std::string(PSLAM_SOURCE_DIR) + "/core/worlds/irregular.yaml";

class EvalMapCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pslam-eval-map-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Exit status of `pslam eval ARGS`; stdout in out_.
  int Run(const std::string& args) {
    const std::string command = std::string(PSLAM_CLI_BINARY) + " eval " + args + " >" + (dir_ / "out.txt").string() +
                                " 2>" + (dir_ / "err.txt").string();
    const int status = std::system(command.c_str());
    std::ifstream in(dir_ / "out.txt");
    out_.assign(std::istreambuf_iterator<char>(in), {});
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
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

  fs::path dir_;
  std::string out_;
};

TEST_F(EvalMapCliTest, AMapThatSitsOffItsFloorPlanIsRightOnceLaidOntoIt) {
  const OccupancyGrid plan = LoadMap(kFloorPlan);
  SaveMap(TransformGrid(plan, Pose2D{0.3, -0.25, 0.0}), (dir_ / "off").string());
  ASSERT_EQ(Run("--json --map " + (dir_ / "off.yaml").string() + " --reference " + kFloorPlan), 0) << out_;
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
  SaveMap(coarse, (dir_ / "coarse").string());
  EXPECT_EQ(Run("--map " + (dir_ / "coarse.yaml").string() + " --reference " + kFloorPlan), 1);
  std::ifstream in(dir_ / "err.txt");
  const std::string err{std::istreambuf_iterator<char>(in), {}};
  EXPECT_NE(err.find("map resolutions differ: reference 0.05 m, evaluated 0.1 m"), std::string::npos) << err;
}

}  // namespace
}  // namespace pslam
