// Motion and measurement models: Jacobians against central finite differences, inverse model, FOV, clutter.
#include <gtest/gtest.h>

#include "backend/models/model_config.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "backend/models/steering_motion.hpp"
#include "backend/models/unicycle_motion.hpp"

namespace glmbslam::backend {
namespace {

template <typename Motion>
void check_motion_jacobians(const Motion& motion, const Pose2& x, const Eigen::Vector2d& u) {
  const double h = 1e-6;
  Eigen::Matrix3d Fx_num;
  for (int i = 0; i < 3; ++i) {
    Pose2 a = x, b = x;
    a(i) += h;
    b(i) -= h;
    Fx_num.col(i) = Motion::local(motion.predict(a, u), motion.predict(b, u)) / (2 * h);
  }
  Eigen::Matrix<double, 3, 2> Fu_num;
  for (int i = 0; i < 2; ++i) {
    Eigen::Vector2d a = u, b = u;
    a(i) += h;
    b(i) -= h;
    Fu_num.col(i) = Motion::local(motion.predict(x, a), motion.predict(x, b)) / (2 * h);
  }
  EXPECT_LT((motion.jacobian_state(x, u) - Fx_num).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((motion.jacobian_control(x, u) - Fu_num).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(UnicycleMotion, JacobiansMatchFiniteDifferences) {
  UnicycleMotion motion;
  check_motion_jacobians(motion, Pose2(1.0, -2.0, 0.3), Eigen::Vector2d(1.1, 0.02));
  check_motion_jacobians(motion, Pose2(1.0, -2.0, 3.1), Eigen::Vector2d(0.9, -0.3));
  check_motion_jacobians(motion, Pose2(5.0, 2.0, -1.0), Eigen::Vector2d(1.0, 0.0));  // straight line
  UnicycleMotionConfig euler;
  euler.euler = true;
  const UnicycleMotion euler_motion(euler);
  check_motion_jacobians(euler_motion, Pose2(1.0, -2.0, 0.3), Eigen::Vector2d(1.1, 0.02));
  const Pose2 e = euler_motion.predict(Pose2(1.0, 2.0, 0.5), Eigen::Vector2d(2.0, 0.1));
  EXPECT_NEAR(e(0), 1.0 + 2.0 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(e(1), 2.0 + 2.0 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(e(2), 0.6, 1e-12);
}

TEST(UnicycleMotion, StraightAndCircularMotion) {
  UnicycleMotionConfig c;
  c.dt = 2.0;
  UnicycleMotion motion(c);
  const Pose2 s = motion.predict(Pose2(0, 0, M_PI / 2), Eigen::Vector2d(1.0, 0.0));
  EXPECT_NEAR(s(0), 0.0, 1e-12);
  EXPECT_NEAR(s(1), 2.0, 1e-12);
  // a quarter circle of radius 1: v = 1, ω = π/4 per s, T = 2 s
  const Pose2 q = motion.predict(Pose2(0, 0, 0), Eigen::Vector2d(1.0, M_PI / 4));
  EXPECT_NEAR(q(0), 4.0 / M_PI, 1e-12);
  EXPECT_NEAR(q(1), 4.0 / M_PI, 1e-12);
  EXPECT_NEAR(q(2), M_PI / 2, 1e-12);
}

TEST(UnicycleMotion, ProcessNoiseIsPositiveDefiniteAndLogDensityPeaksAtPrediction) {
  UnicycleMotion motion;
  const Pose2 x(0, 0, 0.2);
  const Eigen::Vector2d u(1.0, 0.01);
  const Eigen::Matrix3d P = motion.process_noise(x, u);
  EXPECT_EQ(Eigen::LLT<Eigen::Matrix3d>(P).info(), Eigen::Success);
  const Pose2 mean = motion.predict(x, u);
  EXPECT_GT(motion.log_density(mean, x, u), motion.log_density(mean + Pose2(0.1, 0, 0), x, u));
}

TEST(SteeringMotion, JacobiansMatchFiniteDifferences) {
  SteeringMotion motion;
  check_motion_jacobians(motion, Pose2(1.0, -2.0, 0.3), Eigen::Vector2d(1.0, 0.2));
  check_motion_jacobians(motion, Pose2(-1.0, 2.0, -2.9), Eigen::Vector2d(0.5, -0.4));
}

TEST(RangeBearingModel, JacobiansMatchFiniteDifferences) {
  RangeBearingModel model;
  const Pose2 x(1.0, 2.0, 0.7);
  const Eigen::Vector2d m(4.0, 6.5);
  RangeBearingModel::PoseJacobian Hx;
  RangeBearingModel::LandmarkJacobian Hm;
  const Eigen::Vector2d zhat = model.linearize(x, m, &Hx, &Hm);
  EXPECT_LT((zhat - model.predict(x, m)).norm(), 1e-15);
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i) {
    Pose2 a = x, b = x;
    a(i) += h;
    b(i) -= h;
    const Eigen::Vector2d d = model.residual(model.predict(a, m), model.predict(b, m)) / (2 * h);
    EXPECT_LT((Hx.col(i) - d).norm(), 1e-6);
  }
  for (int i = 0; i < 2; ++i) {
    Eigen::Vector2d a = m, b = m;
    a(i) += h;
    b(i) -= h;
    const Eigen::Vector2d d = model.residual(model.predict(x, a), model.predict(x, b)) / (2 * h);
    EXPECT_LT((Hm.col(i) - d).norm(), 1e-6);
  }
}

TEST(RangeBearingModel, InverseModelInvertsPredictAndResidualWraps) {
  RangeBearingModel model;
  const Pose2 x(-3.0, 1.0, 2.5);
  const Eigen::Vector2d z(12.0, -1.2);
  Eigen::Vector2d m;
  Eigen::Matrix2d P;
  model.initialize(x, z, &m, &P);
  EXPECT_LT(model.residual(model.predict(x, m), z).norm(), 1e-12);
  EXPECT_EQ(Eigen::LLT<Eigen::Matrix2d>(P).info(), Eigen::Success);
  EXPECT_NEAR(model.residual(Eigen::Vector2d(1, M_PI - 0.01), Eigen::Vector2d(1, -M_PI + 0.01))(1), -0.02,
              1e-12);
}

TEST(RangeBearingModel, FieldOfViewDetectionSurvivalAndClutter) {
  RangeBearingConfig c;
  c.max_range = 10.0;
  c.half_fov = M_PI / 2;
  c.clutter_rate = 5.0;
  RangeBearingModel model(c);
  const Pose2 x(0, 0, 0);
  EXPECT_TRUE(model.in_field_of_view(x, Eigen::Vector2d(5, 1)));
  EXPECT_FALSE(model.in_field_of_view(x, Eigen::Vector2d(-5, 1)));  // behind
  EXPECT_FALSE(model.in_field_of_view(x, Eigen::Vector2d(11, 0)));  // too far
  EXPECT_FALSE(model.in_field_of_view(x, Eigen::Vector2d(0, 0)));   // at the sensor
  EXPECT_DOUBLE_EQ(model.detection_probability(x, Eigen::Vector2d(5, 1)), 0.95);
  EXPECT_DOUBLE_EQ(model.detection_probability(x, Eigen::Vector2d(-5, 1)), 0.0);
  EXPECT_DOUBLE_EQ(model.survival_probability(x, Eigen::Vector2d(-5, 1)), 1.0);
  EXPECT_NEAR(std::exp(model.log_clutter_intensity(Eigen::Vector2d(1, 0))),
              5.0 / ((10.0 - c.min_range) * M_PI), 1e-12);
  // landmark exactly at the sensor: finite Jacobians
  RangeBearingModel::PoseJacobian Hx;
  RangeBearingModel::LandmarkJacobian Hm;
  const Eigen::Vector2d zhat = model.linearize(x, Eigen::Vector2d(0, 0), &Hx, &Hm);
  EXPECT_TRUE(zhat.allFinite() && Hx.allFinite() && Hm.allFinite());
}

TEST(ModelConfig, LoadsAndRejectsUnknownKeys) {
  RangeBearingConfig c;
  load_range_bearing_config(
      ConfigNode::parse("max_range: 3\nhalf_fov_deg: 180\nsigma_bearing_deg: 0.5\n", "t"), c);
  EXPECT_DOUBLE_EQ(c.max_range, 3.0);
  EXPECT_NEAR(c.half_fov, M_PI, 1e-12);
  EXPECT_THROW(load_range_bearing_config(ConfigNode::parse("max_rnage: 3\n", "t"), c), ConfigError);
  UnicycleMotionConfig u;
  load_unicycle_motion_config(ConfigNode::parse("sigma_omega_deg: 2\n", "t"), u);
  EXPECT_NEAR(u.sigma_omega, 2 * M_PI / 180, 1e-12);
}

}  // namespace
}  // namespace glmbslam::backend
