#include "pslam/eval/map_divergence.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pslam {
namespace {

double Bernoulli(double p, double q) {
  p = std::clamp(p, 1e-3, 1 - 1e-3);
  q = std::clamp(q, 1e-3, 1 - 1e-3);
  return p * std::log(p / q) + (1 - p) * std::log((1 - p) / (1 - q));
}

// A small room spread over several tiles, on both sides of the world origin.
OccupancyGrid Room(double resolution = 0.05) {
  OccupancyGrid grid(resolution);
  for (int y = -70; y <= 70; y += 7) {
    for (int x = -70; x <= 70; x += 5) grid.MutableAt(x, y) = static_cast<OccupancyGrid::Cell>(x * 20 - y * 10);
  }
  return grid;
}

TEST(MapDivergence, IdenticalMapsHaveZeroDivergence) {
  const OccupancyGrid a = Room();
  OccupancyGrid b = Room();
  b.MutableAt(-5000, 4000) = 0;  // same cells, but b's tiles start elsewhere; reference-unknown cell
  const MapDivergence d = ComputeMapDivergence(a, b);
  EXPECT_EQ(d.kl, 0.0);
  EXPECT_EQ(d.cells, 21u * 29u);
}

TEST(MapDivergence, DifferentCellsAddTheirBernoulliDivergence) {
  const OccupancyGrid reference = Room();
  OccupancyGrid evaluated = Room();
  evaluated.MutableAt(10, 14) = -2500;
  evaluated.MutableAt(-70, -70) = 3000;
  const double expected = Bernoulli(reference.Probability(10, 14), evaluated.Probability(10, 14)) +
                          Bernoulli(reference.Probability(-70, -70), evaluated.Probability(-70, -70));
  const MapDivergence d = ComputeMapDivergence(reference, evaluated);
  EXPECT_GT(d.kl, 0.0);
  EXPECT_NEAR(d.kl, expected, 1e-9);
  // Not symmetric: P is the reference.
  EXPECT_NE(ComputeMapDivergence(evaluated, reference).kl, d.kl);
}

TEST(MapDivergence, UnknownCellsFollowTheDocumentedRules) {
  OccupancyGrid reference(0.1);
  reference.MutableAt(-3, 2) = 2000;
  OccupancyGrid evaluated(0.1);
  evaluated.MutableAt(8, 8) = 1000;  // unknown in the reference: ignored
  const MapDivergence d = ComputeMapDivergence(reference, evaluated);
  EXPECT_EQ(d.cells, 1u);  // only reference-known cells
  EXPECT_NEAR(d.kl, Bernoulli(reference.Probability(-3, 2), 0.5), 1e-12);  // unknown in Q -> q = 0.5
}

TEST(MapDivergence, CertainCellsStayFinite) {
  OccupancyGrid reference(0.05), evaluated(0.05);
  reference.MutableAt(0, 0) = 32767;    // p ~ 1
  evaluated.MutableAt(0, 0) = -32767;   // q ~ 0
  const MapDivergence d = ComputeMapDivergence(reference, evaluated);
  EXPECT_TRUE(std::isfinite(d.kl));
  EXPECT_NEAR(d.kl, Bernoulli(1 - 1e-3, 1e-3), 1e-9);
}

TEST(MapDivergence, RejectsDifferentResolutions) {
  EXPECT_THROW(ComputeMapDivergence(Room(0.05), Room(0.1)), std::invalid_argument);
}

}  // namespace
}  // namespace pslam
