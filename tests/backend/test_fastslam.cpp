// FastSLAM 2.0: with known associations and one particle (pose = proposal mean) every step equals an EKF-SLAM
// step (joint Kalman update of pose and landmarks, all measurements in one batch) from the particle's state
// on a linear-Gaussian toy problem; maximum-likelihood association on a range-bearing scene; config
// validation.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "backend/fastslam/fastslam2.hpp"
#include "backend/models/range_bearing_model.hpp"
#include "backend/models/unicycle_motion.hpp"
#include "core/error.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {
namespace {

/// x_k = x_{k−1} + u + ε, ε ~ N(0, Q): a 2D position random walk with a known drift.
struct LinearMotion {
  static constexpr int kDim = 2;
  using State = Eigen::Vector2d;
  using Tangent = Eigen::Vector2d;
  using Covariance = Eigen::Matrix2d;
  using Control = Eigen::Vector2d;
  Covariance Q = Eigen::Vector2d(0.3, 0.2).asDiagonal();
  State predict(const State& x, const Control& u) const { return x + u; }
  Covariance process_noise(const State&, const Control&) const { return Q; }
  State sample(const State& x, const Control& u, RandomStream& rng) const {
    return x + u + rng.gaussian<2>(Tangent::Zero(), Q);
  }
  static State retract(const State& x, const Tangent& d) { return x + d; }
  static Tangent local(const State& a, const State& b) { return a - b; }
};

/// z = m − x + ν, ν ~ N(0, R): the landmark's position relative to the sensor.
struct RelativePositionModel {
  static constexpr int kMeasDim = 2, kLandmarkDim = 2, kPoseDim = 2;
  using Pose = Eigen::Vector2d;
  using Measurement = Eigen::Vector2d;
  using Landmark = Eigen::Vector2d;
  using LandmarkCovariance = Eigen::Matrix2d;
  using MeasurementCovariance = Eigen::Matrix2d;
  using PoseJacobian = Eigen::Matrix2d;
  using LandmarkJacobian = Eigen::Matrix2d;
  MeasurementCovariance R = (Eigen::Matrix2d() << 0.05, 0.01, 0.01, 0.08).finished();
  Measurement linearize(const Pose& x, const Landmark& m, PoseJacobian* H_x, LandmarkJacobian* H_m) const {
    if (H_x != nullptr) *H_x = -Eigen::Matrix2d::Identity();
    if (H_m != nullptr) *H_m = Eigen::Matrix2d::Identity();
    return m - x;
  }
  Measurement residual(const Measurement& z, const Measurement& zhat) const { return z - zhat; }
  const MeasurementCovariance& noise() const { return R; }
  void initialize(const Pose& x, const Measurement& z, Landmark* m, LandmarkCovariance* P) const {
    *m = x + z;
    *P = R;
  }
  double detection_probability(const Pose&, const Landmark&) const { return 1.0; }
  double query_radius() const { return 1e6; }
  static Eigen::Vector2d position(const Pose& x) { return x; }
  static Eigen::Vector2d landmark_position(const Landmark& m) { return m; }
  bool is_finite(const Measurement& z) const { return z.allFinite(); }
};

using ToySlam = FastSlam2<LinearMotion, RelativePositionModel>;

TEST(FastSlam2, KnownAssociationsOneParticleEqualsEkfSlamSteps) {
  const LinearMotion motion;
  const RelativePositionModel model;
  FastSlamConfig cfg;
  cfg.particles = 1;
  cfg.association = "known";
  cfg.single_particle = "mean";
  const Eigen::Vector2d x0(0.0, 0.0);
  ToySlam slam(motion, model, cfg, x0);
  const std::vector<Eigen::Vector2d> landmarks = {{4.0, 1.0}, {-2.0, 3.0}, {1.0, -3.0}};
  RandomStream rng(7, 0);
  Eigen::Vector2d x_true = x0;
  auto measure = [&](const std::vector<int>& ids) {
    ToySlam::MeasurementSet Z;
    for (int i : ids) Z.push_back(landmarks[i] - x_true + rng.gaussian<2>(Eigen::Vector2d::Zero(), model.R));
    return Z;
  };
  // landmarks 0 and 1 at step 0, landmark 2 from step 3 on; measurement order varies
  std::vector<int> ids = {0, 1};
  slam.set_measurement_labels(ids);
  slam.initial_scan(measure(ids));
  for (int k = 1; k <= 8; ++k) {
    const Eigen::Vector2d u(0.5, 0.25 * (k % 3));
    x_true = x_true + u + rng.gaussian<2>(Eigen::Vector2d::Zero(), motion.Q);
    ids = k < 3 ? std::vector<int>{1, 0} : std::vector<int>{2, 0, 1};
    const ToySlam::MeasurementSet Z = measure(ids);
    // the particle's state before the step: the pose (known) and the independent landmark EKFs
    const Eigen::Vector2d x_prev = slam.pose();
    const ToySlam::Map before = slam.map();
    // EKF-SLAM step: joint state [x; m_a; m_b ...] over the landmarks measured and already mapped
    std::vector<int> mapped, rows;
    for (std::size_t j = 0; j < ids.size(); ++j) {
      if (before.find(ids[j]) >= 0) {
        mapped.push_back(before.find(ids[j]));
        rows.push_back(static_cast<int>(j));
      }
    }
    const int n = static_cast<int>(mapped.size());
    const int dim = 2 + 2 * n;
    Eigen::VectorXd mu = Eigen::VectorXd::Zero(dim);
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(dim, dim);
    mu.head<2>() = motion.predict(x_prev, u);
    P.topLeftCorner<2, 2>() = motion.Q;
    for (int i = 0; i < n; ++i) {
      mu.segment<2>(2 + 2 * i) = before.landmarks[static_cast<std::size_t>(mapped[i])].mean;
      P.block<2, 2>(2 + 2 * i, 2 + 2 * i) = before.landmarks[static_cast<std::size_t>(mapped[i])].cov;
    }
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * n, dim);
    Eigen::MatrixXd R = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    Eigen::VectorXd z(2 * n), zhat(2 * n);
    for (int i = 0; i < n; ++i) {
      H.block<2, 2>(2 * i, 0) = -Eigen::Matrix2d::Identity();
      H.block<2, 2>(2 * i, 2 + 2 * i) = Eigen::Matrix2d::Identity();
      R.block<2, 2>(2 * i, 2 * i) = model.R;
      z.segment<2>(2 * i) = Z[static_cast<std::size_t>(rows[i])];
      zhat.segment<2>(2 * i) = mu.segment<2>(2 + 2 * i) - mu.head<2>();
    }
    const Eigen::MatrixXd S = H * P * H.transpose() + R;
    const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
    const Eigen::VectorXd mu_post = mu + K * (z - zhat);
    const Eigen::MatrixXd P_post = (Eigen::MatrixXd::Identity(dim, dim) - K * H) * P;
    const Eigen::VectorXd nu = z - zhat;
    const double log_lik =
        -0.5 * (nu.dot(S.ldlt().solve(nu)) + std::log(S.determinant()) + 2.0 * n * std::log(2.0 * M_PI));

    slam.set_measurement_labels(ids);
    slam.step(u, Z);
    // pose: FastSLAM 2.0's proposal mean = EKF-SLAM's updated pose mean
    EXPECT_NEAR((slam.pose() - mu_post.head<2>()).norm(), 0.0, 1e-9) << "step " << k;
    // weight: the product of the sequential predictive likelihoods = the joint measurement likelihood
    EXPECT_NEAR(slam.last_report().log_likelihood, log_lik, 1e-9) << "step " << k;
    // landmarks: the EKF updated at the pose mean = EKF-SLAM's landmark mean, and its covariance = the
    // EKF-SLAM covariance of the landmark conditioned on the pose (Schur complement)
    const Eigen::Matrix2d Pxx = P_post.topLeftCorner<2, 2>();
    for (int i = 0; i < n; ++i) {
      const auto& l = slam.map().landmarks[static_cast<std::size_t>(mapped[i])];
      EXPECT_NEAR((l.mean - mu_post.segment<2>(2 + 2 * i)).norm(), 0.0, 1e-9) << "step " << k;
      const Eigen::Matrix2d Pmx = P_post.block<2, 2>(2 + 2 * i, 0);
      const Eigen::Matrix2d conditional =
          P_post.block<2, 2>(2 + 2 * i, 2 + 2 * i) - Pmx * Pxx.inverse() * Pmx.transpose();
      EXPECT_NEAR((l.cov - conditional).norm(), 0.0, 1e-9) << "step " << k;
    }
  }
  EXPECT_EQ(slam.map().landmarks.size(), 3u);
  EXPECT_EQ(slam.landmarks().size(), 3u);
  EXPECT_LT((slam.pose() - x_true).norm(), 1.0);
}

TEST(FastSlam2, KnownAssociationsIgnoreClutterAndNeedLabels) {
  FastSlamConfig cfg;
  cfg.particles = 3;
  cfg.association = "known";
  ToySlam slam(LinearMotion(), RelativePositionModel(), cfg, Eigen::Vector2d::Zero());
  ToySlam::MeasurementSet Z = {{1.0, 0.0}, {5.0, 5.0}};
  slam.set_measurement_labels({4, -1});
  slam.initial_scan(Z);
  ASSERT_EQ(slam.map().landmarks.size(), 1u);
  EXPECT_EQ(slam.map().landmarks[0].id, 4);
  slam.set_measurement_labels({4});
  EXPECT_THROW(slam.step(Eigen::Vector2d::Zero(), Z), std::invalid_argument);
}

TEST(FastSlam2, MaximumLikelihoodAssociationTracksARangeBearingScene) {
  UnicycleMotionConfig mc;
  mc.dt = 1.0;
  mc.sigma_v = 0.1;
  mc.sigma_omega = 0.5 * M_PI / 180.0;
  RangeBearingConfig sc;
  sc.max_range = 30.0;
  sc.half_fov = M_PI;
  sc.sigma_range = 0.1;
  sc.sigma_bearing = 0.5 * M_PI / 180.0;
  sc.p_detect_inside = 1.0;
  const UnicycleMotion motion(mc);
  const RangeBearingModel model(sc);
  FastSlamConfig cfg;
  cfg.particles = 5;
  cfg.seed = 3;
  const std::vector<Eigen::Vector2d> landmarks = {{5, 5}, {10, -4}, {15, 6}, {20, -5}, {25, 3}, {8, 12}};
  RandomStream rng(11, 0);
  FastSlam2<UnicycleMotion, RangeBearingModel> slam(motion, model, cfg, Pose2(0, 0, 0));
  Pose2 x(0, 0, 0);
  auto scan = [&] {
    FastSlam2<UnicycleMotion, RangeBearingModel>::MeasurementSet Z;
    for (const auto& m : landmarks) {
      if (!model.in_field_of_view(x, m)) continue;
      Eigen::Vector2d z = model.predict(x, m);
      z(0) += sc.sigma_range * rng.normal();
      z(1) += sc.sigma_bearing * rng.normal();
      Z.push_back(z);
    }
    // one clutter point per scan
    Z.push_back(Eigen::Vector2d(rng.uniform(1.0, 30.0), rng.uniform(-M_PI, M_PI)));
    return Z;
  };
  slam.initial_scan(scan());
  for (int k = 1; k <= 25; ++k) {
    const Eigen::Vector2d u(1.0, 0.0);
    x = motion.predict(x, u);
    slam.step(u, scan());
    // the landmarks are re-associated every scan: nothing but the latest clutter point is new
    EXPECT_GE(slam.last_report().associated, 5) << k;
  }
  EXPECT_LT((slam.pose().head<2>() - x.head<2>()).norm(), 0.5);
  // a clutter landmark is removed at its second missed scan (score 1 − p_D − p_D < 0): the six trees remain,
  // with at most the last two scans' clutter
  const auto est = slam.landmarks();
  EXPECT_GE(est.size(), 6u);
  EXPECT_LE(est.size(), 8u);  // (none: a clutter landmark is detected once)
  for (const auto& m : landmarks) {
    double best = 1e9;
    for (const auto& e : est) best = std::min(best, (e.mean - m).norm());
    EXPECT_LT(best, 0.5);
  }
}

TEST(FastSlam2, ConfigIsValidated) {
  FastSlamConfig cfg;
  cfg.association = "oracle";
  EXPECT_THROW(ToySlam(LinearMotion(), RelativePositionModel(), cfg, Eigen::Vector2d::Zero()), ConfigError);
  cfg = FastSlamConfig();
  cfg.resampling = "never";
  EXPECT_THROW(ToySlam(LinearMotion(), RelativePositionModel(), cfg, Eigen::Vector2d::Zero()), ConfigError);
  cfg = FastSlamConfig();
  cfg.particles = 0;
  EXPECT_THROW(ToySlam(LinearMotion(), RelativePositionModel(), cfg, Eigen::Vector2d::Zero()), ConfigError);
}

}  // namespace
}  // namespace glmbslam::backend
