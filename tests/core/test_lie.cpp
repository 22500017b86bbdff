#include <gtest/gtest.h>

#include "core/lie.hpp"
#include "core/random.hpp"

namespace glmbslam {
namespace {

TEST(Lie, Se3ExpLogRoundTrip) {
  RandomStream rng(7);
  for (int k = 0; k < 100; ++k) {
    Vector6d xi;
    for (int i = 0; i < 6; ++i) xi(i) = rng.uniform(-1.0, 1.0);
    const Vector6d back = se3_log(se3_exp(xi));
    EXPECT_LT((back - xi).norm(), 1e-9);
  }
}

TEST(Lie, MinusInvertsPlus) {
  RandomStream rng(8);
  Vector6d a, d;
  for (int i = 0; i < 6; ++i) {
    a(i) = rng.uniform(-2.0, 2.0);
    d(i) = rng.uniform(-0.5, 0.5);
  }
  const Pose3 T = se3_exp(a);
  EXPECT_LT((se3_minus(se3_plus(T, d), T) - d).norm(), 1e-9);
}

TEST(Lie, AdjointMovesPerturbationAcross) {
  // T Exp(ξ) = Exp(Ad_T ξ) T.
  Vector6d a, xi;
  a << 1.0, -2.0, 0.5, 0.3, -0.2, 0.9;
  xi << 0.01, 0.02, -0.01, 0.003, -0.002, 0.004;
  const Pose3 T = se3_exp(a);
  const Pose3 lhs = T * se3_exp(xi);
  const Pose3 rhs = se3_exp(se3_adjoint(T) * xi) * T;
  EXPECT_LT((lhs.matrix() - rhs.matrix()).norm(), 1e-9);
}

TEST(Lie, WrapAngle) {
  EXPECT_NEAR(wrap_angle(3.0 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrap_angle(-3.0 * M_PI / 2.0), M_PI / 2.0, 1e-12);
  EXPECT_NEAR(wrap_angle(0.1), 0.1, 1e-15);
}

TEST(Lie, RotationAngle) {
  EXPECT_NEAR(rotation_angle(so3_exp(Eigen::Vector3d(0, 0.4, 0))), 0.4, 1e-12);
  // near 0 and π, where acos of the trace resolves only ~1e-8 rad
  EXPECT_NEAR(rotation_angle(so3_exp(Eigen::Vector3d(3e-10, -4e-10, 0))), 5e-10, 1e-20);
  EXPECT_NEAR(rotation_angle(so3_exp(Eigen::Vector3d(0, 0, M_PI - 1e-9))), M_PI - 1e-9, 1e-15);
  EXPECT_NEAR(rotation_angle(so3_exp(Eigen::Vector3d(0.3, -1.2, 2.0))),
              Eigen::Vector3d(0.3, -1.2, 2.0).norm(), 1e-12);
  EXPECT_EQ(rotation_angle(Eigen::Matrix3d::Identity()), 0.0);
}

TEST(Lie, RotationAngleIgnoresASymmetricDeviationFromOrthonormality) {
  // a rotation written with six significant digits, as in KITTI pose files: RᵀR = I + S with S symmetric
  const Eigen::Matrix3d R = so3_exp(Eigen::Vector3d(0.1, 0.7, -0.2));
  const Eigen::Matrix3d R6 = (R * 1e6).array().round().matrix() / 1e6;
  const Eigen::Matrix3d e = R6.transpose() * R6;  // the error of an estimate equal to its ground truth
  EXPECT_GT((e - Eigen::Matrix3d::Identity()).norm(), 1e-8);
  EXPECT_LT(rotation_angle(e), 1e-15);
}

}  // namespace
}  // namespace glmbslam
