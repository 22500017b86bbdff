#pragma once
// Ackermann ("car-like") motion model of the ACFR Victoria Park truck, expressed at the laser position
// (../shared/data/README.md; Guivant & Nebot; paper 003 Sec. VI-B). State x = (x, y, φ) of the laser in the
// GPS frame; one odometry sample u = (v, α) = (speed at the encoder [m/s], steering angle [rad]) held for dt:
//
//   v_c = v / (1 − tan(α)·H/L)
//   x  += dt·v_c·(cos φ − tan α / L · (a sin φ + b cos φ))
//   y  += dt·v_c·(sin φ + tan α / L · (a cos φ − b sin φ))
//   φ  += dt·v_c·tan α / L
//
// with L = 2.83 m (wheel base), H = 0.76 m (encoder offset), a = 3.78 m, b = 0.5 m (laser offsets).
//
// One filter step (laser scan k−1 → k) integrates the odometry samples held between the two scan times, so
// the Control of the MotionModel concept (unicycle_motion.hpp) is a 3×n matrix whose columns are sub-steps
// (v, α, dt): the control held at the previous scan time, then every odometry sample in between, each held
// until the next sample or the scan time (built by src/app/victoria_park_data.hpp, build_scan_controls).
// Noise: each sub-step's control gets an independent ε ~ N(0, Q), Q = diag(σ_v², σ_α²) (the published
// protocol's reference implementation), so
//   P̄ = Σ_i (Π_{j>i} F_x,j) F_ε,i Q F_ε,iᵀ (Π_{j>i} F_x,j)ᵀ + Q_reg       (the EKF recursion over sub-steps)
// with Q_reg = diag(1e-9, 1e-9, 1e-18) keeping P̄ positive definite (digest 2.6). An empty control (no time
// elapsed) leaves the pose unchanged with P̄ = Q_reg.
#include <cmath>

#include <Eigen/Core>

#include "backend/models/unicycle_motion.hpp"
#include "core/gaussian.hpp"
#include "core/lie.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

struct AckermannMotionConfig {
  double wheel_base = 2.83;                        ///< L (m)
  double encoder_offset = 0.76;                    ///< H (m): lateral offset of the speed encoder
  double laser_forward = 3.78;                     ///< a (m): laser ahead of the rear axle (= L + 0.95)
  double laser_lateral = 0.5;                      ///< b (m): laser lateral offset
  double sigma_v = 1.0;                            ///< std of the speed noise (m/s)
  double sigma_steer = 4.0 * M_PI / 180.0;         ///< std of the steering noise (rad)
  Eigen::Vector3d regulariser{1e-9, 1e-9, 1e-18};  ///< added to the diagonal of P̄
};

class AckermannMotion : public Pose2Manifold {
 public:
  /// Columns = sub-steps (v [m/s], α [rad], dt [s]); any number of columns (0 = no motion).
  using Control = Eigen::Matrix<double, 3, Eigen::Dynamic>;
  using SubControl = Eigen::Vector3d;
  using ControlJacobian = Eigen::Matrix<double, 3, 2>;

  AckermannMotion() = default;
  explicit AckermannMotion(const AckermannMotionConfig& config) : config_(config) {}
  const AckermannMotionConfig& config() const { return config_; }

  /// One sub-step f(x, (v, α), dt), optionally with F_x = ∂f/∂x and F_ε = ∂f/∂(v, α).
  State substep(const State& x, double v, double alpha, double dt, Covariance* F_x = nullptr,
                ControlJacobian* F_u = nullptr) const {
    const double L = config_.wheel_base, H = config_.encoder_offset;
    const double a = config_.laser_forward, b = config_.laser_lateral;
    const double t = std::tan(alpha), sec2 = 1.0 + t * t;
    const double denom = 1.0 - t * H / L;
    const double vc = v / denom;
    const double s = std::sin(x(2)), c = std::cos(x(2));
    const double sc = a * s + b * c, cs = a * c - b * s;
    const double m1 = c - sc * t / L, m2 = s + cs * t / L;
    if (F_x != nullptr) {
      F_x->setIdentity();
      (*F_x)(0, 2) = -dt * vc * m2;
      (*F_x)(1, 2) = dt * vc * m1;
    }
    if (F_u != nullptr) {
      const double dvc_dv = 1.0 / denom;
      const double dvc_da = v * (H / L) * sec2 / (denom * denom);
      (*F_u)(0, 0) = dt * dvc_dv * m1;
      (*F_u)(1, 0) = dt * dvc_dv * m2;
      (*F_u)(2, 0) = dt * dvc_dv * t / L;
      (*F_u)(0, 1) = dt * (dvc_da * m1 - vc * sc * sec2 / L);
      (*F_u)(1, 1) = dt * (dvc_da * m2 + vc * cs * sec2 / L);
      (*F_u)(2, 1) = dt * (dvc_da * t / L + vc * sec2 / L);
    }
    return State(x(0) + dt * vc * m1, x(1) + dt * vc * m2, wrap_angle(x(2) + dt * vc * t / L));
  }

  /// f(x, u): the noise-free integration over all sub-steps (also the dead-reckoning model).
  State predict(const State& x, const Control& u) const {
    State y = x;
    for (Eigen::Index i = 0; i < u.cols(); ++i) y = substep(y, u(0, i), u(1, i), u(2, i));
    return y;
  }

  /// F_x of the whole step = Π_i F_x,i (for tests and linearised filters).
  Covariance jacobian_state(const State& x, const Control& u) const {
    State y = x;
    Covariance F = Covariance::Identity(), Fi;
    for (Eigen::Index i = 0; i < u.cols(); ++i) {
      y = substep(y, u(0, i), u(1, i), u(2, i), &Fi, nullptr);
      F = Fi * F;
    }
    return F;
  }

  Eigen::Matrix2d control_noise() const {
    return Eigen::Vector2d(config_.sigma_v * config_.sigma_v, config_.sigma_steer * config_.sigma_steer)
        .asDiagonal();
  }

  /// P̄ = EKF recursion P ← F_x P F_xᵀ + F_ε Q F_εᵀ over the sub-steps from P = 0, plus Q_reg.
  Covariance process_noise(const State& x, const Control& u) const {
    const Eigen::Matrix2d Q = control_noise();
    State y = x;
    Covariance P = Covariance::Zero(), Fx;
    ControlJacobian Fu;
    for (Eigen::Index i = 0; i < u.cols(); ++i) {
      y = substep(y, u(0, i), u(1, i), u(2, i), &Fx, &Fu);
      P = Fx * P * Fx.transpose() + Fu * Q * Fu.transpose();
    }
    symmetrize(P);
    P.diagonal() += config_.regulariser;
    return P;
  }

  /// Draws from the motion model: every sub-step with its own control noise ε_i ~ N(0, Q).
  State sample(const State& x, const Control& u, RandomStream& rng) const {
    State y = x;
    for (Eigen::Index i = 0; i < u.cols(); ++i) {
      const double v = u(0, i) + config_.sigma_v * rng.normal();
      const double alpha = u(1, i) + config_.sigma_steer * rng.normal();
      y = substep(y, v, alpha, u(2, i));
    }
    return y;
  }

  /// log N(x ⊖ f(x_prev, u); 0, P̄).
  double log_density(const State& x, const State& x_prev, const Control& u) const {
    return log_gaussian(local(x, predict(x_prev, u)), process_noise(x_prev, u));
  }

 private:
  AckermannMotionConfig config_;
};

}  // namespace glmbslam::backend
