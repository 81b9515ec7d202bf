#pragma once
// Importance-weight bookkeeping: normalisation in log space, effective sample size, and low-variance
// (systematic) resampling.
#include <random>
#include <vector>

namespace pslam {

// Turns log-weights into normalised weights (sum 1), guarding against underflow.
std::vector<double> NormalizeLogWeights(const std::vector<double>& log_weights);

// N_eff = 1 / sum(w_i^2) for normalised weights.
double EffectiveSampleSize(const std::vector<double>& weights);

// Indices of the particles to keep, one per output slot, drawn with a single random offset; as
// many slots as weights, or 'count' when it is given (an adaptive particle count).
std::vector<int> SystematicResample(const std::vector<double>& weights, std::mt19937_64& rng, int count = -1);

}  // namespace pslam
