#include "pslam/io/map_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <unistd.h>

namespace pslam {
namespace {

namespace fs = std::filesystem;

constexpr double kResolution = 0.05;
constexpr int kOccupied = 3000;   // milli log-odds, p ~ 0.95
constexpr int kFree = -2000;      // p ~ 0.12
constexpr int kUncertain = 0;     // p = 0.5: known to us, unknown in a trinary image

// Cells on both sides of the world origin, so negative indices and origins are exercised.
OccupancyGrid MakeGrid() {
  OccupancyGrid grid(kResolution);
  grid.MutableAt(-3, -2) = kOccupied;
  grid.MutableAt(4, 5) = kOccupied;
  grid.MutableAt(-1, 0) = kFree;
  grid.MutableAt(0, -1) = kFree;
  grid.MutableAt(2, 3) = kFree;
  grid.MutableAt(1, 1) = kUncertain;
  return grid;
}

enum class Class { kOccupied, kFree, kUnknown };

Class Classify(const OccupancyGrid& grid, int cx, int cy) {
  if (!grid.IsKnown(cx, cy)) return Class::kUnknown;
  const double p = grid.Probability(cx, cy);
  if (p > kMapOccupiedThreshold) return Class::kOccupied;
  if (p < kMapFreeThreshold) return Class::kFree;
  return Class::kUnknown;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

class MapIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) / ("pslam_map_io_" + std::string(info->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Every cell of the saved window keeps its class, and the loaded cells sit at the same world
  // coordinates (looked up by world point, not by index).
  void ExpectSameMap(const OccupancyGrid& original, const OccupancyGrid& loaded) {
    EXPECT_DOUBLE_EQ(loaded.resolution(), original.resolution());
    for (int cy = -4; cy <= 7; ++cy) {
      for (int cx = -5; cx <= 6; ++cx) {
        const Eigen::Vector2i in_loaded = loaded.WorldToCell(original.CellCenter({cx, cy}));
        EXPECT_EQ(Classify(loaded, in_loaded.x(), in_loaded.y()), Classify(original, cx, cy)) << cx << "," << cy;
      }
    }
    EXPECT_FALSE(loaded.IsKnown(1, 1));  // uncertain cells come back unknown (trinary)
    const CellBox box = loaded.KnownBounds();
    EXPECT_EQ(box.min, Eigen::Vector2i(-3, -2));
    EXPECT_EQ(box.max, Eigen::Vector2i(4, 5));
  }

  fs::path dir_;
};

TEST_F(MapIoTest, RendersKnownBoundsWithMarginTopRowFirst) {
  const MapImage image = RenderMapImage(MakeGrid());
  // Known cells span x -3..4 and y -2..5; a 1-cell margin makes the window -4..5 x -3..6.
  EXPECT_EQ(image.width, 10);
  EXPECT_EQ(image.height, 10);
  EXPECT_NEAR(image.origin.x(), -4 * kResolution, 1e-12);
  EXPECT_NEAR(image.origin.y(), -3 * kResolution, 1e-12);
  const auto pixel = [&](int cx, int cy) { return image.pixels[static_cast<std::size_t>(6 - cy) * image.width + (cx + 4)]; };
  EXPECT_EQ(pixel(-3, -2), kMapPixelOccupied);
  EXPECT_EQ(pixel(4, 5), kMapPixelOccupied);  // near the top: row 1
  EXPECT_EQ(image.pixels[1 * 10 + 8], kMapPixelOccupied);
  EXPECT_EQ(pixel(-1, 0), kMapPixelFree);
  EXPECT_EQ(pixel(1, 1), kMapPixelUnknown);
  EXPECT_EQ(pixel(-4, 6), kMapPixelUnknown);  // margin
}

TEST_F(MapIoTest, EmptyGridRendersAsSmallUnknownImage) {
  const MapImage image = RenderMapImage(OccupancyGrid(0.1));
  EXPECT_EQ(image.width, 3);
  EXPECT_EQ(image.height, 3);
  for (std::uint8_t p : image.pixels) EXPECT_EQ(p, kMapPixelUnknown);
}

TEST_F(MapIoTest, PgmYamlRoundTripKeepsWorldCoordinates) {
  const OccupancyGrid grid = MakeGrid();
  const std::string prefix = (dir_ / "map").string();
  SaveMap(grid, prefix);

  const std::string yaml = ReadText(prefix + ".yaml");
  EXPECT_NE(yaml.find("image: map.pgm\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("resolution: 0.05\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("origin: [-0.2, -0.15, 0.0]\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("negate: 0\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("occupied_thresh: 0.65\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("free_thresh: 0.196\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("mode: trinary\n"), std::string::npos) << yaml;
  const std::string pgm = ReadText(prefix + ".pgm");
  EXPECT_EQ(pgm.rfind("P5\n", 0), 0u);
  EXPECT_NE(pgm.find("\n10 10\n255\n"), std::string::npos);

  const OccupancyGrid loaded = LoadMap(prefix + ".yaml");
  ExpectSameMap(grid, loaded);
  EXPECT_GT(loaded.Probability(-3, -2), 0.9);
  EXPECT_LT(loaded.Probability(2, 3), 0.15);

  // Saving the loaded map again gives the same image and YAML.
  const std::string again = (dir_ / "again").string();
  SaveMap(loaded, again);
  EXPECT_EQ(ReadText(again + ".pgm"), pgm);
}

TEST_F(MapIoTest, ParsedFromMemoryLikeLoadedFromFiles) {
  const OccupancyGrid grid = MakeGrid();
  const MapImage image = RenderMapImage(grid);
  const std::string pgm = MapPgmBytes(image), yaml = MapYamlText(image, "any-name.pgm");
  const OccupancyGrid parsed = ParseMap(yaml, pgm, "upload");
  ExpectSameMap(grid, parsed);
  EXPECT_EQ(MapPgmBytes(RenderMapImage(parsed)), pgm);
  // Errors name what was parsed, not a file.
  try {
    ParseMap(yaml, pgm.substr(0, pgm.size() - 5), "upload");
    FAIL() << "a truncated raster was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("upload (image): size mismatch"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseMap("image: a.pgm\nresolution: 0.05\n", pgm, "upload"), std::runtime_error);  // no origin
}

TEST_F(MapIoTest, PngRoundTripAndInMemoryEncodingMatch) {
  const OccupancyGrid grid = MakeGrid();
  const std::string prefix = (dir_ / "map").string();
  SaveMap(grid, prefix);
  const std::vector<std::uint8_t> png = EncodeMapPng(grid);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(std::string(png.begin(), png.end()), ReadText(prefix + ".png"));

  // Point a YAML (in another folder, relative path) at the PNG.
  fs::create_directories(dir_ / "png");
  fs::rename(prefix + ".png", dir_ / "png" / "map.png");
  WriteText(dir_ / "png" / "map.yaml",
            "image: \"map.png\"  # quoted, with a comment\nresolution: 0.05\norigin: [ -0.2 , -0.15, 0 ]\n"
            "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\nunrelated_key: 7\n");
  ExpectSameMap(grid, LoadMap((dir_ / "png" / "map.yaml").string()));
}

TEST_F(MapIoTest, ReadsAsciiPgmWithNegateAndScaleMode) {
  // 3x2 image, maxval 100; with negate, brightness is occupancy: 100 -> occupied, 0 -> free.
  WriteText(dir_ / "a.pgm", "P2\n# ascii\n3 2\n100\n100 0 50\n0 # inline comment\n 10 100\n");
  WriteText(dir_ / "a.yaml", "image: a.pgm\nresolution: 0.5\norigin: [1.0, -0.5, 0.0]\nnegate: 1\n"
                             "occupied_thresh: 0.6\nfree_thresh: 0.2\nmode: scale\n");
  const OccupancyGrid grid = LoadMap((dir_ / "a.yaml").string());
  EXPECT_DOUBLE_EQ(grid.resolution(), 0.5);
  // Origin (1.0, -0.5) is cell (2, -1); row 0 (top) is cell row y = 0.
  EXPECT_GT(grid.Probability(2, 0), 0.9);   // 100
  EXPECT_LT(grid.Probability(3, 0), 0.15);  // 0
  EXPECT_TRUE(grid.IsKnown(4, 0));          // 50: scale mode keeps it as p = 0.5
  EXPECT_NEAR(grid.Probability(4, 0), 0.5, 1e-3);
  EXPECT_LT(grid.Probability(2, -1), 0.15);  // 0
  EXPECT_LT(grid.Probability(3, -1), 0.15);  // 10 -> 0.1 < free_thresh
  EXPECT_GT(grid.Probability(4, -1), 0.9);
  EXPECT_FALSE(grid.IsKnown(5, 0));
  EXPECT_FALSE(grid.IsKnown(2, 1));
}

TEST_F(MapIoTest, BadInputsNameTheFile) {
  WriteText(dir_ / "ok.pgm", std::string("P5\n2 2\n255\n\xfe\xfe\x00\xcd", 15));
  const auto expect_error = [&](const std::string& yaml_text, const std::string& what, const fs::path& file) {
    const fs::path yaml = dir_ / "bad.yaml";
    WriteText(yaml, yaml_text);
    try {
      LoadMap(yaml.string());
      ADD_FAILURE() << "no error for: " << yaml_text;
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(file.string()), std::string::npos) << message;
      EXPECT_NE(message.find(what), std::string::npos) << message;
    }
  };
  const fs::path yaml = dir_ / "bad.yaml";
  const std::string origin = "origin: [0, 0, 0]\n";
  expect_error("resolution: 0.05\n" + origin, "missing key 'image'", yaml);
  expect_error("image: ok.pgm\n" + origin, "missing key 'resolution'", yaml);
  expect_error("image: ok.pgm\nresolution: 0.05\n", "missing key 'origin'", yaml);
  expect_error("image: ok.pgm\nresolution: 0\n" + origin, "'resolution' must be positive", yaml);
  expect_error("image: ok.pgm\nresolution: fine\n" + origin, "'resolution' is not a number", yaml);
  expect_error("image: ok.pgm\nresolution: 0.05\norigin: [0, 0]\n", "'origin' must have 3 values", yaml);
  expect_error("image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0.5]\n", "yaw", yaml);
  expect_error("image: ok.pgm\nimage: ok.pgm\nresolution: 0.05\n" + origin, "duplicate key 'image'", yaml);
  expect_error("image: ok.pgm\nresolution: 0.05\nmode: raw\n" + origin, "unsupported 'mode'", yaml);
  expect_error("image: ok.pgm\nresolution: 0.05\nnegate: maybe\n" + origin, "'negate'", yaml);
  expect_error("image: ok.pgm\nthis line has no colon\n", "line 2", yaml);

  expect_error("image: missing.pgm\nresolution: 0.05\n" + origin, "cannot open map image", dir_ / "missing.pgm");
  WriteText(dir_ / "junk.png", "this is not an image");
  expect_error("image: junk.png\nresolution: 0.05\n" + origin, "unreadable map image", dir_ / "junk.png");
  WriteText(dir_ / "short.pgm", "P5\n4 4\n255\nabc");
  expect_error("image: short.pgm\nresolution: 0.05\n" + origin, "size mismatch", dir_ / "short.pgm");
  WriteText(dir_ / "short2.pgm", "P2\n2 2\n255\n1 2 3\n");
  expect_error("image: short2.pgm\nresolution: 0.05\n" + origin, "size mismatch", dir_ / "short2.pgm");
  WriteText(dir_ / "huge.pgm", "P5\n1048576 1048576\n255\nabc");
  expect_error("image: huge.pgm\nresolution: 0.05\n" + origin, "size mismatch", dir_ / "huge.pgm");
  WriteText(dir_ / "empty.png", "");
  expect_error("image: empty.png\nresolution: 0.05\n" + origin, "empty", dir_ / "empty.png");
  WriteText(dir_ / "range.pgm", "P2\n1 1\n100\n101\n");
  expect_error("image: range.pgm\nresolution: 0.05\n" + origin, "bad PGM pixel", dir_ / "range.pgm");

  EXPECT_THROW(LoadMap((dir_ / "nowhere.yaml").string()), std::runtime_error);
  EXPECT_THROW(SaveMap(MakeGrid(), (dir_ / "no_such_dir" / "map").string()), std::runtime_error);
}

}  // namespace
}  // namespace pslam
