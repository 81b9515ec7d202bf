#include "pslam/localize/particle_clusters.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <unordered_set>

namespace pslam {
namespace {

constexpr int kBinLimit = (1 << 20) - 1;  // bins per axis each side of 0: a wild pose saturates

struct Bin {
  int x, y, t;
};

int HeadingBins(const PoseBinning& b) {
  return std::max(1, static_cast<int>(std::lround(2.0 * std::numbers::pi / b.theta)));
}

int Clamp(double v) {
  if (!(v > -kBinLimit)) return -kBinLimit;  // also NaN
  return v > kBinLimit ? kBinLimit : static_cast<int>(v);
}

Bin BinOf(const Pose2D& p, const PoseBinning& b, int heading_bins) {
  const double t = (p.theta + std::numbers::pi) / (2.0 * std::numbers::pi) * heading_bins;
  return {Clamp(std::floor(p.x / b.xy)), Clamp(std::floor(p.y / b.xy)),
          std::clamp(static_cast<int>(t), 0, heading_bins - 1)};
}

std::uint64_t Key(const Bin& b) {
  const auto u = [](int v) { return static_cast<std::uint64_t>(v + kBinLimit); };
  return (u(b.x) << 42) | (u(b.y) << 21) | static_cast<std::uint64_t>(b.t);
}

// Accumulates weighted pose statistics.
struct Moments {
  double w = 0.0, x = 0.0, y = 0.0, xx = 0.0, xy = 0.0, yy = 0.0, c = 0.0, s = 0.0;
  int n = 0;
  void Add(const Pose2D& p, double weight) {
    w += weight;
    x += weight * p.x;
    y += weight * p.y;
    xx += weight * p.x * p.x;
    xy += weight * p.x * p.y;
    yy += weight * p.y * p.y;
    c += weight * std::cos(p.theta);
    s += weight * std::sin(p.theta);
    ++n;
  }
  ParticleCluster Finish() const {
    ParticleCluster out;
    out.weight = w;
    out.particles = n;
    if (!(w > 0.0)) return out;
    const double mx = x / w, my = y / w;
    out.mean = Pose2D(mx, my, std::atan2(s, c));
    out.position_covariance << xx / w - mx * mx, xy / w - mx * my, xy / w - mx * my, yy / w - my * my;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(out.position_covariance, Eigen::EigenvaluesOnly);
    out.position_std = std::sqrt(std::max(0.0, eigen.eigenvalues()(1)));
    const double resultant = std::min(1.0, std::hypot(c, s) / w);
    out.heading_std = resultant > 0.0 ? std::sqrt(-2.0 * std::log(resultant)) : std::numbers::pi;
    return out;
  }
};

}  // namespace

int CountOccupiedBins(const std::vector<Pose2D>& poses, const PoseBinning& binning) {
  const int heading_bins = HeadingBins(binning);
  std::unordered_set<std::uint64_t> bins;
  bins.reserve(poses.size());
  for (const Pose2D& p : poses) bins.insert(Key(BinOf(p, binning, heading_bins)));
  return static_cast<int>(bins.size());
}

int KldSampleCount(int k, double err, double z, int min_count, int max_count) {
  if (k <= 1) return min_count;
  // Wilson-Hilferty approximation of the chi-square quantile (Fox 2003, eq. 7).
  const double b = 2.0 / (9.0 * (k - 1));
  const double x = 1.0 - b + std::sqrt(b) * z;
  const double n = std::ceil((k - 1) / (2.0 * err) * x * x * x);
  return static_cast<int>(std::clamp(n, static_cast<double>(min_count), static_cast<double>(max_count)));
}

std::vector<ParticleCluster> ClusterParticles(const std::vector<Pose2D>& poses, const std::vector<double>& weights,
                                              const PoseBinning& binning) {
  const int heading_bins = HeadingBins(binning);
  std::unordered_map<std::uint64_t, std::vector<int>> members;
  std::unordered_map<std::uint64_t, Bin> bin_of_key;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Bin b = BinOf(poses[i], binning, heading_bins);
    const std::uint64_t key = Key(b);
    members[key].push_back(static_cast<int>(i));
    bin_of_key.emplace(key, b);
  }
  // Flood fill over touching bins. Keys are visited in particle order, so the result does not
  // depend on the hash map's iteration order.
  std::unordered_set<std::uint64_t> done;
  std::vector<ParticleCluster> clusters;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::uint64_t seed = Key(BinOf(poses[i], binning, heading_bins));
    if (!done.insert(seed).second) continue;
    Moments m;
    std::vector<std::uint64_t> stack{seed};
    while (!stack.empty()) {
      const std::uint64_t key = stack.back();
      stack.pop_back();
      for (int j : members[key]) m.Add(poses[static_cast<std::size_t>(j)], weights[static_cast<std::size_t>(j)]);
      const Bin b = bin_of_key[key];
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dt = -1; dt <= 1; ++dt) {
            const Bin n{b.x + dx, b.y + dy, (b.t + dt + heading_bins) % heading_bins};
            const std::uint64_t nk = Key(n);
            if (members.count(nk) && done.insert(nk).second) stack.push_back(nk);
          }
        }
      }
    }
    clusters.push_back(m.Finish());
  }
  std::stable_sort(clusters.begin(), clusters.end(),
                   [](const ParticleCluster& a, const ParticleCluster& b) { return a.weight > b.weight; });
  return clusters;
}

ParticleCluster SummarizeParticles(const std::vector<Pose2D>& poses, const std::vector<double>& weights) {
  Moments m;
  for (std::size_t i = 0; i < poses.size(); ++i) m.Add(poses[i], weights[i]);
  return m.Finish();
}

}  // namespace pslam
