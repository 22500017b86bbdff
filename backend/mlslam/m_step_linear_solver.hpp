#pragma once
// The M-step's Ceres linear solver from MlSlamConfig::linear_solver and the problem's pose count: one choice
// for RfsMlSlam (the windows, the 2D solves) and StereoMStepProblem (the final pass).
#include <cstddef>

#include <ceres/types.h>

#include "backend/mlslam/mlslam_config.hpp"

namespace glmbslam::backend {

/// "auto": dense Schur up to MlSlamConfig::kAutoDensePoses poses (the reduced pose system is small and dense:
/// Eigen's Cholesky, no sparse analysis and no BLAS threads), sparse Schur up to kAutoSchurPoses, sparse
/// normal Cholesky beyond.
inline ceres::LinearSolverType m_step_linear_solver(const MlSlamConfig& c, std::size_t poses) {
  if (c.linear_solver == "iterative_schur") return ceres::ITERATIVE_SCHUR;
  if (c.linear_solver == "dense_schur") return ceres::DENSE_SCHUR;
  if (c.linear_solver == "sparse_schur") return ceres::SPARSE_SCHUR;
  if (c.linear_solver == "sparse_normal_cholesky") return ceres::SPARSE_NORMAL_CHOLESKY;
  if (poses <= MlSlamConfig::kAutoDensePoses) return ceres::DENSE_SCHUR;
  if (poses <= MlSlamConfig::kAutoSchurPoses) return ceres::SPARSE_SCHUR;
  return ceres::SPARSE_NORMAL_CHOLESKY;
}

}  // namespace glmbslam::backend
