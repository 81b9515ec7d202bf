#include "pslam/filter/resampling.hpp"

#include <algorithm>
#include <cmath>

namespace pslam {

std::vector<double> NormalizeLogWeights(const std::vector<double>& log_weights) {
  std::vector<double> w(log_weights.size());
  if (w.empty()) return w;
  const double top = *std::max_element(log_weights.begin(), log_weights.end());
  double sum = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) sum += (w[i] = std::exp(log_weights[i] - top));
  for (double& x : w) x /= sum;
  return w;
}

double EffectiveSampleSize(const std::vector<double>& weights) {
  double s = 0.0;
  for (double w : weights) s += w * w;
  return s > 0.0 ? 1.0 / s : 0.0;
}

std::vector<int> SystematicResample(const std::vector<double>& weights, std::mt19937_64& rng, int count) {
  const int n = static_cast<int>(weights.size());
  const int slots = count < 0 ? n : count;
  std::vector<int> picks(static_cast<std::size_t>(n == 0 ? 0 : slots));
  if (n == 0 || slots == 0) return picks;
  const double step = 1.0 / slots;
  double u = std::uniform_real_distribution<double>(0.0, step)(rng);
  double cumulative = weights[0];
  int i = 0;
  for (int slot = 0; slot < slots; ++slot, u += step) {
    while (u > cumulative && i < n - 1) cumulative += weights[static_cast<std::size_t>(++i)];
    picks[static_cast<std::size_t>(slot)] = i;
  }
  return picks;
}

}  // namespace pslam
