#include <cmath>

#include <gtest/gtest.h>

#include "core/lie.hpp"
#include "core/random.hpp"
#include "eval/alignment.hpp"
#include "io/trajectory_io.hpp"
#include "support/test_data.hpp"

namespace glmbslam::eval {
namespace {

Eigen::Matrix3d random_rotation(RandomStream& rng) {
  Eigen::Vector3d phi(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
  return so3_exp(phi.normalized() * rng.uniform(0.0, 3.1));
}

TEST(Umeyama, RecoversKnownSimilarity) {
  RandomStream rng(21);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 3 + static_cast<int>(rng.index(50));
    Eigen::Matrix3Xd src(3, n);
    for (int i = 0; i < n; ++i) src.col(i) = Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal()) * 10.0;
    const Eigen::Matrix3d R = random_rotation(rng);
    const Eigen::Vector3d t(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50));
    const double s = rng.uniform(0.2, 5.0);
    const Eigen::Matrix3Xd dst = ((s * R) * src).colwise() + t;
    const Similarity3 a = umeyama_alignment(src, dst, true);
    EXPECT_NEAR(a.scale, s, 1e-9 * s);
    EXPECT_LT((a.rotation - R).norm(), 1e-9);
    EXPECT_LT((a.translation - t).norm(), 1e-7);
    EXPECT_NEAR(a.rotation.determinant(), 1.0, 1e-12);
    // Without scale the rotation is still recovered exactly (the optimal R does not depend on s).
    const Similarity3 rigid = umeyama_alignment(src, dst, false);
    EXPECT_DOUBLE_EQ(rigid.scale, 1.0);
    EXPECT_LT((rigid.rotation - R).norm(), 1e-9);
  }
}

TEST(Umeyama, NeverReturnsAReflection) {
  // Target = mirror image of a planar-ish cloud: the best proper rotation, not the reflection.
  Eigen::Matrix3Xd src(3, 4);
  src << 1, 0, 0, 1,  //
      0, 1, 0, 1,     //
      0, 0, 1, 1;
  Eigen::Matrix3Xd dst = src;
  dst.row(0) *= -1.0;
  const Similarity3 a = umeyama_alignment(src, dst, true);
  EXPECT_NEAR(a.rotation.determinant(), 1.0, 1e-12);
  EXPECT_LT((a.rotation.transpose() * a.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(Ate, ZeroForTransformedTrajectoryAndScaleReported) {
  RandomStream rng(5);
  PoseList gt;
  for (int i = 0; i < 40; ++i) {
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi(k) = rng.uniform(-1.0, 1.0);
    xi.head<3>() *= 20.0;
    gt.push_back(se3_exp(xi));
  }
  // est = S⁻¹ applied to gt positions with a known similarity: Sim(3) ATE 0 and scale s recovered.
  const Eigen::Matrix3d R = random_rotation(rng);
  const Eigen::Vector3d t(3, -4, 5);
  const double s = 0.8;
  PoseList est = gt;
  for (auto& T : est) T.translation() = R.transpose() * (T.translation() - t) / s;  // gt = s R est + t
  const AteResult a = evaluate_ate(gt, est);
  EXPECT_EQ(a.poses, 40);
  EXPECT_NEAR(a.sim3_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(a.sim3_scale, s, 1e-9);
  EXPECT_GT(a.se3_rmse_m, 0.1);  // a rigid alignment cannot absorb the scale
  // With s = 1 the SE(3) alignment is exact too.
  for (auto& T : est) T.translation() *= s;  // est now = Rᵀ(gt − t)
  const AteResult b = evaluate_ate(gt, est);
  EXPECT_NEAR(b.se3_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(b.sim3_scale, 1.0, 1e-9);
}

TEST(Ate, HandComputedOffset) {
  // Ground truth on the x axis at x = 0..3; the estimate is offset by +1, −1, −1, +1 m along y. The offsets
  // have zero mean and zero correlation with x, so no translation or rotation reduces them (a rotation about
  // x keeps every distance to the axis at 1 m): the SE(3) RMSE is exactly 1 m.
  PoseList gt, est;
  for (int i = 0; i < 4; ++i) {
    Pose3 T = Pose3::Identity();
    T.translation() = Eigen::Vector3d(i, 0, 0);
    gt.push_back(T);
  }
  const double dy[4] = {1, -1, -1, 1};  // symmetric about the centre: no rotation reduces the error
  for (int i = 0; i < 4; ++i) {
    Pose3 T = gt[static_cast<size_t>(i)];
    T.translation().y() += dy[i];
    est.push_back(T);
  }
  const AteResult a = evaluate_ate(gt, est);
  EXPECT_NEAR(a.se3_rmse_m, 1.0, 1e-9);
}

TEST(Ate, StillGroundTruthLeavesSim3Undefined) {
  // A still camera: the ground truth stays at one point and the estimate jitters by millimetres around it.
  // A similarity would shrink the estimate onto the point (scale 0, error 0); Sim(3) is undefined instead,
  // and SE(3) keeps the jitter.
  PoseList gt(20, Pose3::Identity()), est;
  for (int i = 0; i < 20; ++i) {
    Pose3 T = Pose3::Identity();
    T.translation() = Eigen::Vector3d(0.002 * std::sin(i), 0.001 * std::cos(3 * i), 0.0);
    est.push_back(T);
  }
  const AteResult a = evaluate_ate(gt, est);
  EXPECT_TRUE(std::isnan(a.sim3_scale));
  EXPECT_TRUE(std::isnan(a.sim3_rmse_m));
  EXPECT_TRUE(a.sim3_errors_m.empty());
  EXPECT_GT(a.se3_rmse_m, 5e-4);
  EXPECT_EQ(a.se3_errors_m.size(), 20u);
  // a ground truth that moves by more than kMinSim3Spread keeps its Sim(3)
  gt[10].translation().x() = 1e-3;
  EXPECT_TRUE(std::isfinite(evaluate_ate(gt, est).sim3_scale));
}

TEST(Ate, SizeMismatchAndEmptyThrow) {
  PoseList one(1, Pose3::Identity());
  EXPECT_THROW(evaluate_ate(one, PoseList{}), std::invalid_argument);
  EXPECT_THROW(evaluate_ate(PoseList{}, PoseList{}), std::invalid_argument);
}

TEST(Ate, OracleSequence00) {
  GLMBSLAM_REQUIRE_DATA(odometry, "kitti_odometry");
  const PoseList gt = io::read_kitti_poses((odometry / "poses/00.txt").string());
  const AteResult orb =
      evaluate_ate(gt, io::read_kitti_poses((odometry / "results/00_orbslam2_stereo.txt").string()));
  EXPECT_NEAR(orb.se3_rmse_m, 1.3034, 1e-3 * 1.3034);
  EXPECT_NEAR(orb.sim3_rmse_m, 0.9377, 1e-3 * 0.9377);
  EXPECT_NEAR(orb.sim3_scale, 1.00470, 1e-3 * 1.00470);
  const AteResult sptam =
      evaluate_ate(gt, io::read_kitti_poses((odometry / "results/00_sptam.txt").string()));
  EXPECT_NEAR(sptam.se3_rmse_m, 3.7385, 1e-3 * 3.7385);
  EXPECT_NEAR(sptam.sim3_rmse_m, 3.6353, 1e-3 * 3.6353);
}

}  // namespace
}  // namespace glmbslam::eval
