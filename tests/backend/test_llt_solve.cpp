// llt_solve reproduces Eigen's LLT::solve bit for bit (2×2 factor: 2×2 and 2×3 right-hand sides; 3×3 factor:
// 3×3 and 3×6 right-hand sides; plain matrices and products), on random well- and ill-conditioned systems.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "backend/glmb/llt_solve.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {
namespace {

template <class M>
bool bit_equal(const M& a, const M& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

/// Entries N(0, 1) times 10^U(−e, e).
template <int R, int C>
Eigen::Matrix<double, R, C> random_matrix(RandomStream& rng, double e) {
  Eigen::Matrix<double, R, C> m;
  for (int i = 0; i < R * C; ++i) m.data()[i] = rng.normal() * std::pow(10.0, rng.uniform(-e, e));
  return m;
}

/// A random SPD matrix with condition numbers up to ~10¹⁴.
template <int N>
Eigen::Matrix<double, N, N> random_spd(RandomStream& rng) {
  const Eigen::Matrix<double, N, N> A = random_matrix<N, N>(rng, 0.0);
  Eigen::Matrix<double, N, N> S = std::pow(10.0, rng.uniform(-6.0, 6.0)) * A * A.transpose();
  S.diagonal().array() += std::pow(10.0, rng.uniform(-8.0, 2.0));
  return S;
}

/// Right-hand sides N×N and N×C, and the products N×C·C×C and N×N·N×N (as the callers pass them).
template <int N, int C>
void expect_bit_identical(std::uint64_t seed, int trials) {
  RandomStream rng(seed, 0);
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::Matrix<double, N, N> S = random_spd<N>(rng);
    const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(S);
    ASSERT_EQ(llt.info(), Eigen::Success);
    const Eigen::Matrix<double, N, N> B = random_matrix<N, N>(rng, 3.0);
    const Eigen::Matrix<double, N, C> H = random_matrix<N, C>(rng, 3.0);
    const Eigen::Matrix<double, C, C> P = random_matrix<C, C>(rng, 1.0);
    ASSERT_TRUE(
        bit_equal(Eigen::Matrix<double, N, N>(llt_solve(llt, B)), Eigen::Matrix<double, N, N>(llt.solve(B))))
        << S << "\n"
        << B;
    ASSERT_TRUE(
        bit_equal(Eigen::Matrix<double, N, C>(llt_solve(llt, H)), Eigen::Matrix<double, N, C>(llt.solve(H))))
        << S << "\n"
        << H;
    ASSERT_TRUE(bit_equal(Eigen::Matrix<double, N, C>(llt_solve(llt, H * P)),
                          Eigen::Matrix<double, N, C>(llt.solve(H * P))));
    ASSERT_TRUE(bit_equal(Eigen::Matrix<double, N, N>(llt_solve(llt, B * S)),
                          Eigen::Matrix<double, N, N>(llt.solve(B * S))));
  }
}

TEST(LltSolve, BitIdenticalToEigen2x2) {
  expect_bit_identical<2, 3>(7, 20000);
}

TEST(LltSolve, BitIdenticalToEigen3x3) {
  expect_bit_identical<3, 6>(11, 20000);
}

}  // namespace
}  // namespace glmbslam::backend
