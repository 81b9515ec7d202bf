#include "pslam/graph/pose_graph.hpp"

#include <ceres/ceres.h>

#include <array>
#include <stdexcept>

namespace pslam {
namespace {

template <typename T>
T WrapAngle(const T& a) {
  using std::atan2, std::sin, std::cos;  // ceres::Jet overloads are found by argument lookup
  return atan2(sin(a), cos(a));
}

// r = sqrt_info * [R_a^T (t_b - t_a) - t_ab ; wrap(theta_b - theta_a - theta_ab)]
class RelativePoseError {
 public:
  RelativePoseError(const Pose2D& measurement, const Eigen::Matrix3d& sqrt_information)
      : measurement_(measurement), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* a, const T* b, T* residual) const {
    using std::cos, std::sin;
    const T c = cos(a[2]), s = sin(a[2]);
    const T dx = b[0] - a[0], dy = b[1] - a[1];
    Eigen::Matrix<T, 3, 1> e;
    e(0) = c * dx + s * dy - T(measurement_.x);
    e(1) = -s * dx + c * dy - T(measurement_.y);
    e(2) = WrapAngle(b[2] - a[2] - T(measurement_.theta));
    const Eigen::Matrix<T, 3, 1> r = sqrt_information_.cast<T>() * e;
    for (int i = 0; i < 3; ++i) residual[i] = r(i);
    return true;
  }

 private:
  Pose2D measurement_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace

int PoseGraph::AddNode(const Pose2D& pose) {
  poses_.push_back(pose);
  return static_cast<int>(poses_.size()) - 1;
}

void PoseGraph::AddEdge(const PoseGraphEdge& edge) {
  if (edge.from < 0 || edge.to < 0 || edge.from >= size() || edge.to >= size() || edge.from == edge.to) {
    throw std::invalid_argument("pose graph edge between unknown nodes");
  }
  edges_.push_back(edge);
}

double PoseGraph::Mahalanobis(const PoseGraphEdge& edge) const {
  const RelativePoseError error(edge.measurement, edge.sqrt_information);
  const Pose2D& a = pose(edge.from);
  const Pose2D& b = pose(edge.to);
  const std::array<double, 3> pa{a.x, a.y, a.theta}, pb{b.x, b.y, b.theta};
  std::array<double, 3> r{};
  error(pa.data(), pb.data(), r.data());
  return Eigen::Vector3d(r[0], r[1], r[2]).norm();
}

PoseGraphSolveSummary PoseGraph::Optimize(const PoseGraphSolveOptions& options) {
  PoseGraphSolveSummary out;
  if (poses_.size() < 2 || edges_.empty()) return out;
  std::vector<std::array<double, 3>> params(poses_.size());
  for (std::size_t i = 0; i < poses_.size(); ++i) params[i] = {poses_[i].x, poses_[i].y, poses_[i].theta};

  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges_) {
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 3, 3, 3>(
        new RelativePoseError(e.measurement, e.sqrt_information));
    ceres::LossFunction* loss = e.huber_scale > 0.0 ? new ceres::HuberLoss(e.huber_scale) : nullptr;
    problem.AddResidualBlock(cost, loss, params[static_cast<std::size_t>(e.from)].data(),
                             params[static_cast<std::size_t>(e.to)].data());
  }
  problem.SetParameterBlockConstant(params[0].data());

  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = options.threads;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  for (std::size_t i = 0; i < poses_.size(); ++i) poses_[i] = Pose2D(params[i][0], params[i][1], params[i][2]);
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  return out;
}

}  // namespace pslam
