#pragma once
// A histogram of particle poses in (x, y, theta) bins, as KLD sampling and AMCL's cluster
// estimate use it: how many bins a set occupies, and the clusters of adjacent occupied bins with
// their weight, mean and spread.
#include <Eigen/Core>
#include <vector>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct PoseBinning {
  double xy = 0.5;      // m
  double theta = 0.17;  // rad; rounded so that a whole number of bins spans the circle
};

// Number of distinct bins the poses fall in.
int CountOccupiedBins(const std::vector<Pose2D>& poses, const PoseBinning& binning);

// Fox's bound: the samples needed for KL divergence <= err with normal quantile z, for k bins.
// One bin or none needs no more than the floor; the result is clamped to [min_count, max_count].
int KldSampleCount(int k, double err, double z, int min_count, int max_count);

struct ParticleCluster {
  double weight = 0.0;                                  // share of the total weight
  int particles = 0;
  Pose2D mean;                                          // weighted; circular mean heading
  Eigen::Matrix2d position_covariance = Eigen::Matrix2d::Zero();
  double position_std = 0.0;  // m, along the widest direction (square root of the largest eigenvalue)
  double heading_std = 0.0;   // rad, circular standard deviation
};

// Clusters of particles whose bins touch (26-neighbourhood, heading wrapping around), heaviest
// first. 'weights' are normalised and parallel to 'poses'.
std::vector<ParticleCluster> ClusterParticles(const std::vector<Pose2D>& poses, const std::vector<double>& weights,
                                              const PoseBinning& binning);

// The statistics of all particles as one cluster.
ParticleCluster SummarizeParticles(const std::vector<Pose2D>& poses, const std::vector<double>& weights);

}  // namespace pslam
