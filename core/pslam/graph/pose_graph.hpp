#pragma once
// A sparse 2D pose graph: nodes are robot poses, edges relative-pose measurements between two of
// them with a square-root information matrix. Optimised with Ceres (Levenberg-Marquardt, sparse
// Cholesky); loop-closure edges carry a robust loss so that one wrong closure cannot bend the map.
#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "pslam/common/pose2d.hpp"

namespace pslam {

struct PoseGraphEdge {
  int from = 0;
  int to = 0;
  Pose2D measurement;                         // pose of `to` in the frame of `from`
  Eigen::Matrix3d sqrt_information = Eigen::Matrix3d::Identity();
  double huber_scale = 0.0;                   // > 0: robust (loop closure) edge
};

struct PoseGraphSolveOptions {
  int max_iterations = 30;
  int threads = 1;
};

struct PoseGraphSolveSummary {
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
};

class PoseGraph {
 public:
  int AddNode(const Pose2D& pose);
  void AddEdge(const PoseGraphEdge& edge);
  // Removes the edges for which `drop` is true; returns how many.
  template <typename Predicate>
  int RemoveEdgesIf(Predicate drop) {
    const auto end = std::remove_if(edges_.begin(), edges_.end(), drop);
    const int removed = static_cast<int>(edges_.end() - end);
    edges_.erase(end, edges_.end());
    return removed;
  }
  // Moves every node but the first (the anchor) to minimise the weighted edge residuals.
  PoseGraphSolveSummary Optimize(const PoseGraphSolveOptions& options = {});

  int size() const { return static_cast<int>(poses_.size()); }
  const Pose2D& pose(int node) const { return poses_[static_cast<std::size_t>(node)]; }
  const std::vector<Pose2D>& poses() const { return poses_; }
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  // Whitened residual norm of an edge at the current poses: in standard deviations.
  double Mahalanobis(const PoseGraphEdge& edge) const;

 private:
  std::vector<Pose2D> poses_;
  std::vector<PoseGraphEdge> edges_;
};

}  // namespace pslam
