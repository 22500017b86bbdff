#pragma once
// Gaussian densities in log space, for fixed- or dynamic-size Eigen types.
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace glmbslam {

/// log N(r; 0, S) for a residual r and covariance S (S must be symmetric positive definite).
/// Returns −∞ when S is not positive definite.
template <typename Residual, typename Covariance>
double log_gaussian(const Eigen::MatrixBase<Residual>& r, const Eigen::MatrixBase<Covariance>& S) {
  using Mat = typename Covariance::PlainObject;
  const Eigen::LLT<Mat> llt(S.eval());
  if (llt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
  const auto L = llt.matrixL();
  const auto y = L.solve(r.eval());
  double log_det = 0.0;
  for (Eigen::Index i = 0; i < S.rows(); ++i) log_det += std::log(llt.matrixLLT()(i, i));
  log_det *= 2.0;
  const double d = static_cast<double>(S.rows());
  return -0.5 * (d * std::log(2.0 * M_PI) + log_det + y.squaredNorm());
}

/// Squared Mahalanobis distance rᵀ S⁻¹ r (+∞ when S is not positive definite).
template <typename Residual, typename Covariance>
double mahalanobis_squared(const Eigen::MatrixBase<Residual>& r, const Eigen::MatrixBase<Covariance>& S) {
  using Mat = typename Covariance::PlainObject;
  const Eigen::LLT<Mat> llt(S.eval());
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return llt.matrixL().solve(r.eval()).squaredNorm();
}

/// Symmetrises a covariance in place: P ← (P + Pᵀ)/2.
template <typename Matrix>
void symmetrize(Eigen::MatrixBase<Matrix>& P) {
  P = (0.5 * (P + P.transpose())).eval();
}

}  // namespace glmbslam
