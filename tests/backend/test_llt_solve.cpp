// llt_solve reproduces Eigen's LLT::solve bit for bit (2×2 factor, 2×2 and 2×3 right-hand sides), on random
// well- and ill-conditioned systems.
#include <gtest/gtest.h>

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

TEST(LltSolve, BitIdenticalToEigen) {
  RandomStream rng(7, 0);
  int compared = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Eigen::Matrix2d A;
    A << rng.normal(), rng.normal(), rng.normal(), rng.normal();
    const double scale = std::pow(10.0, rng.uniform(-6.0, 6.0));
    Eigen::Matrix2d S = scale * A * A.transpose();
    S.diagonal().array() += std::pow(10.0, rng.uniform(-8.0, 2.0));
    const Eigen::LLT<Eigen::Matrix2d> llt(S);
    ASSERT_EQ(llt.info(), Eigen::Success);
    Eigen::Matrix2d B2;
    Eigen::Matrix<double, 2, 3> B3;
    for (int i = 0; i < 4; ++i) B2.data()[i] = rng.normal() * std::pow(10.0, rng.uniform(-3.0, 3.0));
    for (int i = 0; i < 6; ++i) B3.data()[i] = rng.normal() * std::pow(10.0, rng.uniform(-3.0, 3.0));
    const Eigen::Matrix2d e2 = llt.solve(B2);
    const Eigen::Matrix<double, 2, 3> e3 = llt.solve(B3);
    ASSERT_TRUE(bit_equal(Eigen::Matrix2d(llt_solve(llt, B2)), e2)) << S << "\n" << B2;
    ASSERT_TRUE(bit_equal(Eigen::Matrix<double, 2, 3>(llt_solve(llt, B3)), e3)) << S << "\n" << B3;
    // products as right-hand sides (as the callers use it)
    const Eigen::Matrix<double, 2, 3> H = B3;
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() * scale;
    const Eigen::Matrix<double, 2, 3> e_prod = llt.solve(H * P);
    ASSERT_TRUE(bit_equal(Eigen::Matrix<double, 2, 3>(llt_solve(llt, H * P)), e_prod));
    compared += 3;
  }
  EXPECT_EQ(compared, 60000);
}

}  // namespace
}  // namespace glmbslam::backend
