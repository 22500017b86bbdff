// The 3D models of the stereo pipeline: stereo measurement Jacobians against finite differences, the inverse
// model against the forward model, and the SE(3) motion model's manifold operations.
#include <gtest/gtest.h>

#include "backend/models/se3_motion.hpp"
#include "backend/models/stereo_measurement_model.hpp"
#include "core/random.hpp"
#include "stereo_test_support.hpp"

namespace glmbslam::backend {
namespace {

using test::kitti_calibration;

Pose3 random_pose(RandomStream& rng) {
  Vector6d xi;
  for (int i = 0; i < 6; ++i) xi(i) = rng.uniform(-0.5, 0.5);
  return se3_exp(xi);
}

TEST(StereoMeasurementModel, JacobiansMatchFiniteDifferences) {
  const StereoMeasurementModel model(kitti_calibration(), StereoMeasurementConfig{});
  RandomStream rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose3 x = random_pose(rng);
    const Eigen::Vector3d m = x * Eigen::Vector3d(rng.uniform(-3, 3), rng.uniform(-1, 1), rng.uniform(4, 18));
    StereoMeasurementModel::PoseJacobian Hx;
    StereoMeasurementModel::LandmarkJacobian Hm;
    const Eigen::Vector3d z0 = model.linearize(x, m, &Hx, &Hm);
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      Vector6d d = Vector6d::Zero();
      d(k) = h;
      const Eigen::Vector3d num =
          (model.predict(se3_plus(x, d), m) - model.predict(se3_plus(x, -d), m)) / (2 * h);
      EXPECT_LT((num - Hx.col(k)).norm(), 1e-4 * (1.0 + num.norm())) << "pose column " << k;
    }
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d(k) = h;
      const Eigen::Vector3d num = (model.predict(x, m + d) - model.predict(x, m - d)) / (2 * h);
      EXPECT_LT((num - Hm.col(k)).norm(), 1e-4 * (1.0 + num.norm())) << "landmark column " << k;
    }
    EXPECT_LT((z0 - model.predict(x, m)).norm(), 1e-12);
  }
}

TEST(StereoMeasurementModel, InverseModelInvertsPrediction) {
  const StereoMeasurementModel model(kitti_calibration(), StereoMeasurementConfig{});
  RandomStream rng(4);
  const Pose3 x = random_pose(rng);
  const Eigen::Vector3d z(500.0, 200.0, 470.0);
  Eigen::Vector3d m;
  Eigen::Matrix3d P;
  model.initialize(x, z, &m, &P);
  EXPECT_LT((model.predict(x, m) - z).norm(), 1e-9);
  // The covariance maps back to the pixel noise, H_m P H_mᵀ = σ² I, up to the 1e-9 m² diagonal regulariser.
  StereoMeasurementModel::LandmarkJacobian Hm;
  model.linearize(x, m, nullptr, &Hm);
  const double regulariser_effect = (Hm * Hm.transpose()).norm() * 1e-9;
  EXPECT_LT((Hm * P * Hm.transpose() - model.noise()).norm(), 1e-9 + 1.01 * regulariser_effect);
}

TEST(StereoMeasurementModel, FieldOfViewAndDetection) {
  StereoMeasurementConfig cfg;
  cfg.max_depth = 20.0;
  const StereoMeasurementModel model(kitti_calibration(), cfg);
  const Pose3 x = Pose3::Identity();
  EXPECT_TRUE(model.in_field_of_view(x, Eigen::Vector3d(0, 0, 10)));
  EXPECT_FALSE(model.in_field_of_view(x, Eigen::Vector3d(0, 0, 25)));   // beyond z_max
  EXPECT_FALSE(model.in_field_of_view(x, Eigen::Vector3d(0, 0, -5)));   // behind
  EXPECT_FALSE(model.in_field_of_view(x, Eigen::Vector3d(30, 0, 10)));  // outside the image
  EXPECT_EQ(model.detection_probability(x, Eigen::Vector3d(0, 0, 25)), 0.0);
  EXPECT_EQ(model.survival_probability(x, Eigen::Vector3d(0, 0, 25)), 1.0);
  EXPECT_EQ(model.detection_probability(x, Eigen::Vector3d(0, 0, 10)), cfg.p_detect_inside);
  EXPECT_FALSE(model.is_finite(Eigen::Vector3d(100, 100, 120)));  // negative disparity
}

TEST(Se3Motion, SampleIsCentredOnPredictionWithGivenCovariance) {
  const Se3Motion motion;
  RandomStream rng(5);
  RelativePoseControl u;
  u.delta = se3_exp((Vector6d() << 0.1, 0.0, 0.9, 0.0, 0.02, 0.0).finished());
  u.covariance = Vector6d(1e-4, 2e-4, 4e-4, 1e-6, 2e-6, 3e-6).asDiagonal();
  const Pose3 x0 = random_pose(rng);
  const Pose3 pred = motion.predict(x0, u);
  const int n = 20000;
  Vector6d mean = Vector6d::Zero();
  Matrix6d cov = Matrix6d::Zero();
  for (int i = 0; i < n; ++i) {
    const Vector6d d = Se3Motion::local(motion.sample(x0, u, rng), pred);
    mean += d;
    cov += d * d.transpose();
  }
  mean /= n;
  cov /= n;
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(mean(i), 0.0, 4.0 * std::sqrt(u.covariance(i, i) / n));
    EXPECT_NEAR(cov(i, i), u.covariance(i, i), 0.05 * u.covariance(i, i));
  }
  // The density peaks at the prediction.
  EXPECT_GT(motion.log_density(pred, x0, u),
            motion.log_density(Se3Motion::retract(pred, mean * 0 + Vector6d::Constant(0.01)), x0, u));
}

}  // namespace
}  // namespace glmbslam::backend
