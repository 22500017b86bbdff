#pragma once
// S⁻¹ B for a 2×2 Cholesky factor and a 2×n right-hand side, computed with exactly the floating-point
// operations of Eigen 3.4's LLT::solve for a matrix right-hand side (triangular_solve_matrix: L then Lᵀ,
// each row scaled by the reciprocal of its diagonal), without its blocking and packing overhead, which
// dominates at this size. Bit-identical results (tests/backend/test_llt_solve.cpp checks them against
// Eigen); any other size or LLT goes to Eigen.
#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace glmbslam::backend {

/// Any other LLT: Eigen's solve.
template <class MatrixType, class Rhs>
typename Rhs::PlainObject llt_solve(const Eigen::LLT<MatrixType>& llt, const Eigen::MatrixBase<Rhs>& b) {
  return llt.solve(b);
}

template <class Rhs>
auto llt_solve(const Eigen::LLT<Eigen::Matrix2d>& llt, const Eigen::MatrixBase<Rhs>& b) ->
    typename Rhs::PlainObject {
  typename Rhs::PlainObject x = b;
  if constexpr (Rhs::RowsAtCompileTime == 2 && Rhs::ColsAtCompileTime != Eigen::Dynamic &&
                Rhs::ColsAtCompileTime > 1) {
    const Eigen::Matrix2d& L = llt.matrixLLT();
    const double l10 = L(1, 0);
    const double a0 = 1.0 / L(0, 0);
    const double a1 = 1.0 / L(1, 1);
    for (int j = 0; j < Rhs::ColsAtCompileTime; ++j) {
      // L y = b (column-major lower kernel)
      double x0 = x(0, j) * a0;
      double x1 = x(1, j) - x0 * l10;
      x1 *= a1;
      // Lᵀ z = y (row-major upper kernel)
      x1 = (x1 - 0.0) * a1;
      double s = 0.0;
      s += l10 * x1;
      x0 = (x0 - s) * a0;
      x(0, j) = x0;
      x(1, j) = x1;
    }
  } else {
    x = llt.solve(b);
  }
  return x;
}

}  // namespace glmbslam::backend
