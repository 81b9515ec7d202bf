#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "pslam/filter/motion_model.hpp"
#include "pslam/filter/resampling.hpp"

namespace pslam {
namespace {

TEST(MotionModel, SamplesCentreOnTheMotionWithSpreadGrowingWithDistance) {
  std::mt19937_64 rng(7);
  const MotionNoise noise{.rotation_per_rotation = 0.05,
                          .rotation_per_translation = 0.02,
                          .translation_per_translation = 0.03,
                          .translation_per_rotation = 0.01};
  auto spread = [&](const Pose2D& delta, double* mean_x) {
    double sx = 0, sxx = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      const double x = SampleMotion(delta, noise, rng).x;
      sx += x;
      sxx += x * x;
    }
    *mean_x = sx / n;
    return std::sqrt(sxx / n - (*mean_x) * (*mean_x));
  };
  double mean_short = 0, mean_long = 0;
  const double short_sd = spread(Pose2D(0.5, 0, 0), &mean_short);
  const double long_sd = spread(Pose2D(2.0, 0, 0), &mean_long);
  EXPECT_NEAR(mean_short, 0.5, 0.005);
  EXPECT_NEAR(mean_long, 2.0, 0.01);
  // Translation noise is proportional to the distance: 0.03 m per metre.
  EXPECT_NEAR(short_sd, 0.015, 0.002);
  EXPECT_NEAR(long_sd / short_sd, 4.0, 0.4);
}

TEST(MotionModel, PureRotationStaysInPlace) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 100; ++i) {
    const Pose2D p = SampleMotion(Pose2D(0, 0, 1.0), MotionNoise{.rotation_per_rotation = 0.1}, rng);
    EXPECT_LT(std::hypot(p.x, p.y), 0.1);
    EXPECT_NEAR(p.theta, 1.0, 0.3);
  }
}

TEST(Resampling, NormalizesLogWeightsWithoutUnderflow) {
  const auto w = NormalizeLogWeights({-10000.0, -10001.0, -10000.0});
  EXPECT_NEAR(std::accumulate(w.begin(), w.end(), 0.0), 1.0, 1e-12);
  EXPECT_NEAR(w[0], w[2], 1e-12);
  EXPECT_NEAR(w[0] / w[1], std::exp(1.0), 1e-9);
}

TEST(Resampling, EffectiveSampleSizeSpansOneToN) {
  EXPECT_NEAR(EffectiveSampleSize({0.25, 0.25, 0.25, 0.25}), 4.0, 1e-12);
  EXPECT_NEAR(EffectiveSampleSize({1.0, 0.0, 0.0, 0.0}), 1.0, 1e-12);
}

TEST(Resampling, SystematicResamplingKeepsCountsProportionalToWeights) {
  std::mt19937_64 rng(11);
  const std::vector<double> w = {0.5, 0.25, 0.125, 0.125, 0.0};
  std::vector<int> counts(5, 0);
  for (int i : SystematicResample(std::vector<double>(w), rng)) ++counts[static_cast<std::size_t>(i)];
  // With 5 slots a particle of weight w gets floor(5w) or ceil(5w) copies.
  EXPECT_GE(counts[0], 2);
  EXPECT_LE(counts[0], 3);
  EXPECT_EQ(counts[4], 0);
  EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), 0), 5);
}

TEST(Resampling, SystematicResamplingDrawsAnyNumberOfSlots) {
  std::mt19937_64 rng(11);
  const std::vector<double> w = {0.5, 0.25, 0.25, 0.0};
  std::vector<int> counts(4, 0);
  for (int i : SystematicResample(w, rng, 8)) ++counts[static_cast<std::size_t>(i)];
  EXPECT_EQ(counts, (std::vector<int>{4, 2, 2, 0}));  // 8 w exactly: a comb of 8 teeth
  EXPECT_EQ(SystematicResample(w, rng, 2).size(), 2u);
  EXPECT_TRUE(SystematicResample(w, rng, 0).empty());
}

}  // namespace
}  // namespace pslam
