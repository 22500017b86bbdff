// Stereo projection model and its Jacobians against central finite differences; triangulation consistency.
#include <gtest/gtest.h>

#include "core/random.hpp"
#include "frontend/stereo_projection.hpp"

namespace glmbslam::frontend {
namespace {

const StereoCamera kCam(721.5377, 721.5377, 609.5593, 172.854, 0.5371506);

Pose3 random_pose(RandomStream& rng) {
  Vector6d xi;
  for (int i = 0; i < 3; ++i) xi(i) = rng.uniform(-2.0, 2.0);
  for (int i = 3; i < 6; ++i) xi(i) = rng.uniform(-0.3, 0.3);
  return se3_exp(xi);
}

TEST(StereoProjection, TriangulateInvertsProject) {
  RandomStream rng(1);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d p(rng.uniform(-10, 10), rng.uniform(-3, 3), rng.uniform(1, 60));
    EXPECT_LT((kCam.triangulate(kCam.project(p)) - p).norm(), 1e-9 * p.norm());
    // ∂π⁻¹/∂z is the inverse of ∂π/∂p.
    const Eigen::Matrix3d prod = kCam.triangulate_jacobian(kCam.project(p)) * kCam.project_jacobian(p);
    EXPECT_LT((prod - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  }
}

TEST(StereoProjection, PointJacobianMatchesFiniteDifferences) {
  RandomStream rng(2);
  for (int trial = 0; trial < 50; ++trial) {
    const Pose3 T = random_pose(rng);
    const Eigen::Vector3d m = T * Eigen::Vector3d(rng.uniform(-5, 5), rng.uniform(-2, 2), rng.uniform(2, 40));
    Matrix36d Jpose;
    Eigen::Matrix3d Jpoint;
    kCam.project_from_pose(T, m, &Jpose, &Jpoint);
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d(k) = h;
      const Eigen::Vector3d fd =
          (kCam.project_from_pose(T, m + d) - kCam.project_from_pose(T, m - d)) / (2 * h);
      EXPECT_LT((fd - Jpoint.col(k)).norm(), 1e-5 * (1.0 + Jpoint.col(k).norm())) << "column " << k;
    }
  }
}

TEST(StereoProjection, PoseJacobianMatchesFiniteDifferencesRightPerturbation) {
  RandomStream rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const Pose3 T = random_pose(rng);
    const Eigen::Vector3d m = T * Eigen::Vector3d(rng.uniform(-5, 5), rng.uniform(-2, 2), rng.uniform(2, 40));
    Matrix36d Jpose;
    kCam.project_from_pose(T, m, &Jpose, nullptr);
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      Vector6d xi = Vector6d::Zero();
      xi(k) = h;
      const Eigen::Vector3d fd =
          (kCam.project_from_pose(se3_plus(T, xi), m) - kCam.project_from_pose(se3_plus(T, -xi), m)) /
          (2 * h);
      EXPECT_LT((fd - Jpose.col(k)).norm(), 1e-5 * (1.0 + Jpose.col(k).norm())) << "column " << k;
    }
  }
}

TEST(StereoProjection, TriangulationJacobianMatchesFiniteDifferences) {
  RandomStream rng(4);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Vector3d z(rng.uniform(50, 1200), rng.uniform(20, 350), 0.0);
    const Eigen::Vector3d zz(z.x(), z.y(), z.x() - rng.uniform(3, 150));
    const Eigen::Matrix3d J = kCam.triangulate_jacobian(zz);
    const double h = 1e-5;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d(k) = h;
      const Eigen::Vector3d fd = (kCam.triangulate(zz + d) - kCam.triangulate(zz - d)) / (2 * h);
      EXPECT_LT((fd - J.col(k)).norm(), 1e-5 * (1.0 + J.col(k).norm())) << "column " << k;
    }
  }
}

// Synthetic two-camera projection with Gaussian pixel noise: the triangulation error normalised by the
// propagated covariance has E[eᵀP⁻¹e] = 3 (χ² with 3 dof) to first order. Depths 2–25 m keep the disparity
// (≥ 15 px) large against σ = 0.5 px, where the first-order propagation holds.
TEST(StereoTriangulation, NormalisedErrorMatchesPropagatedCovariance) {
  RandomStream rng(5);
  const int n = 4000;
  const double sigma = 0.5;
  double nees_sum = 0.0;
  int within_95 = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p(rng.uniform(-8, 8), rng.uniform(-2, 2), rng.uniform(2, 25));
    Eigen::Vector3d z = kCam.project(p);
    for (int k = 0; k < 3; ++k) z(k) += rng.normal(0.0, sigma);
    const Eigen::Vector3d est = kCam.triangulate(z);
    const Eigen::Matrix3d P = kCam.triangulation_covariance(z, sigma);
    const Eigen::Vector3d e = est - p;
    const double nees = e.dot(P.ldlt().solve(e));
    nees_sum += nees;
    if (nees < 7.815) ++within_95;
  }
  const double mean = nees_sum / n;
  // Standard error of the mean of χ²₃ over 4000 samples: √(6/4000) ≈ 0.04.
  EXPECT_NEAR(mean, 3.0, 0.25);
  EXPECT_NEAR(static_cast<double>(within_95) / n, 0.95, 0.02);
}

}  // namespace
}  // namespace glmbslam::frontend
