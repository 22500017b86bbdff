#pragma once
// S⁻¹ B for a 2×2 or 3×3 Cholesky factor and a right-hand side with a fixed number (> 1) of columns, computed
// with exactly the floating-point operations of Eigen 3.4's LLT::solve for a matrix right-hand side
// (triangular_solve_matrix: L then Lᵀ, each row scaled by the reciprocal of its diagonal; at these sizes the
// whole triangle is one of its small panels, so no blocked update takes part), without its blocking and
// packing overhead, which dominates at this size (the stereo filters' Kalman gains: 3×3 S, 3×6 and 3×3
// right-hand sides). Bit-identical results (tests/backend/test_llt_solve.cpp checks them against Eigen); any
// other size or LLT goes to Eigen.
#include <type_traits>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace glmbslam::backend {

/// Any other LLT: Eigen's solve.
template <class MatrixType, class Rhs>
typename Rhs::PlainObject llt_solve(const Eigen::LLT<MatrixType>& llt, const Eigen::MatrixBase<Rhs>& b) {
  return llt.solve(b);
}

/// N = 2 or 3: Eigen's operations, column by column (the columns are independent).
template <int N, class Rhs, std::enable_if_t<N == 2 || N == 3, int> = 0>
auto llt_solve(const Eigen::LLT<Eigen::Matrix<double, N, N>>& llt, const Eigen::MatrixBase<Rhs>& b) ->
    typename Rhs::PlainObject {
  typename Rhs::PlainObject x = b;
  if constexpr (Rhs::RowsAtCompileTime == N && Rhs::ColsAtCompileTime != Eigen::Dynamic &&
                Rhs::ColsAtCompileTime > 1) {
    const Eigen::Matrix<double, N, N>& L = llt.matrixLLT();
    double inv[N];
    for (int k = 0; k < N; ++k) inv[k] = 1.0 / L(k, k);
    for (int j = 0; j < Rhs::ColsAtCompileTime; ++j) {
      // L y = b (column-major lower kernel): scale row k, then remove it from the rows below
      for (int k = 0; k < N; ++k) {
        x(k, j) *= inv[k];
        const double y = x(k, j);
        for (int r = k + 1; r < N; ++r) x(r, j) -= y * L(r, k);
      }
      // Lᵀ z = y (row-major upper kernel): from the last row up, the dot product with the rows solved
      for (int i = N - 1; i >= 0; --i) {
        double s = 0.0;
        for (int r = i + 1; r < N; ++r) s += L(r, i) * x(r, j);
        x(i, j) = (x(i, j) - s) * inv[i];
      }
    }
  } else {
    x = llt.solve(b);
  }
  return x;
}

}  // namespace glmbslam::backend
