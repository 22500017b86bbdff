#include "backend/mlslam/loop_pose_graph.hpp"

#include <stdexcept>

#include <ceres/problem.h>
#include <ceres/solver.h>
#include <Eigen/Cholesky>

#include "backend/mlslam/ceres_factors_3d.hpp"

namespace glmbslam::backend {

namespace {

/// W with Wᵀ W = Σ⁻¹: the inverse of the Cholesky factor L of Σ = L Lᵀ.
Matrix6d whitening(const Matrix6d& covariance) {
  const Eigen::LLT<Matrix6d> llt(covariance);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("loop pose graph: an odometry covariance is not positive definite");
  return llt.matrixL().solve(Matrix6d::Identity());
}

/// The squared whitened residual of a loop constraint at `poses`.
double loop_chi2(const LoopConstraint& c, const PoseVector& poses) {
  double a[kPose3BlockSize], b[kPose3BlockSize];
  pose3_to_block(poses[c.i], a);
  pose3_to_block(poses[c.j], b);
  const RelativePoseResidual r{Eigen::Quaterniond(c.relative.linear()).normalized(), c.relative.translation(),
                               c.W};
  Eigen::Matrix<double, 6, 1> e;
  r(a, b, e.data());
  return e.squaredNorm();
}

/// One solve of the graph from `start` with the loops `active`; the result goes to `poses`.
LoopPoseGraphReport solve(const PoseVector& start, const Matrix6dVector& W,
                          const std::vector<LoopConstraint>& active, int max_iterations, PoseVector& poses) {
  const std::size_t n = start.size();
  std::vector<double> blocks(n * kPose3BlockSize);
  for (std::size_t k = 0; k < n; ++k) pose3_to_block(start[k], &blocks[k * kPose3BlockSize]);
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  Pose3CeresManifold manifold;
  for (std::size_t k = 0; k < n; ++k)
    problem.AddParameterBlock(&blocks[k * kPose3BlockSize], kPose3BlockSize, &manifold);
  problem.SetParameterBlockConstant(&blocks[0]);
  for (std::size_t k = 1; k < n; ++k) {
    const Pose3 u = start[k - 1].inverse() * start[k];  // the filter's own motion: its local shape
    problem.AddResidualBlock(make_relative_pose_factor(u, W[k]), nullptr, &blocks[(k - 1) * kPose3BlockSize],
                             &blocks[k * kPose3BlockSize]);
  }
  for (const auto& c : active) {
    problem.AddResidualBlock(make_relative_pose_factor(c.relative, c.W), nullptr,
                             &blocks[c.i * kPose3BlockSize], &blocks[c.j * kPose3BlockSize]);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;  // the same result at any thread count
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  poses.resize(n);
  for (std::size_t k = 0; k < n; ++k) poses[k] = pose3_from_block(&blocks[k * kPose3BlockSize]);
  LoopPoseGraphReport report;
  report.iterations = static_cast<int>(summary.iterations.size());
  report.initial_cost = summary.initial_cost;
  report.final_cost = summary.final_cost;
  report.loops_used = static_cast<int>(active.size());
  return report;
}

}  // namespace

LoopPoseGraphReport optimise_loop_pose_graph(PoseVector& poses, const Matrix6dVector& odometry_covariance,
                                             const std::vector<LoopConstraint>& loops, double gate,
                                             int max_iterations) {
  const std::size_t n = poses.size();
  if (odometry_covariance.size() != n)
    throw std::invalid_argument("loop pose graph: one odometry covariance per pose is needed");
  for (const auto& c : loops)
    if (c.i >= n || c.j >= n || c.i == c.j)
      throw std::invalid_argument("loop pose graph: a loop constraint names a frame outside the trajectory");
  if (n < 2 || loops.empty()) return {};
  Matrix6dVector W(n, Matrix6d::Identity());
  for (std::size_t k = 1; k < n; ++k) W[k] = whitening(odometry_covariance[k]);
  const PoseVector start = poses;
  // greedy: solve, drop the loop with the largest residual above the gate, solve again from the start
  std::vector<LoopConstraint> kept = loops;
  int rejected = 0;
  for (;;) {
    if (kept.empty()) {
      poses = start;
      LoopPoseGraphReport none;
      none.loops_rejected = rejected;
      return none;
    }
    LoopPoseGraphReport report = solve(start, W, kept, max_iterations, poses);
    std::size_t worst = kept.size();
    double worst_chi2 = gate;
    for (std::size_t l = 0; l < kept.size(); ++l) {
      const double chi2 = loop_chi2(kept[l], poses);
      if (chi2 > worst_chi2) {
        worst_chi2 = chi2;
        worst = l;
      }
    }
    if (worst == kept.size()) {
      report.loops_rejected = rejected;
      return report;
    }
    kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(worst));
    ++rejected;
  }
}

}  // namespace glmbslam::backend
