#pragma once
// 2D velocity ("unicycle") motion model, paper 003 Eq. 49: pose x = (x, y, θ), control u = (v, ω), time step
// T.
//
//   f(x, u) = [x − v/ω sin θ + v/ω sin(θ + ωT),  y + v/ω cos θ − v/ω cos(θ + ωT),  θ + ωT]ᵀ
//
// with the straight-line limit for |ω| → 0. Control noise ε ~ N(0, Q), Q = diag(σ_v², σ_ω²), enters
// additively on u. The state-space process covariance is F_ε Q F_εᵀ + Q_reg (digest 2.6: rank 2, so a small
// regulariser Q_reg = diag(1e-9, 1e-9, 1e-18) keeps it positive definite for log densities).
//
// MotionModel concept (what backend/glmb and backend/rbpf use):
//   using State, Tangent (Eigen::Matrix<double,kDim,1>), Covariance (kDim×kDim), Control, ControlNoise;
//   static constexpr int kDim;                       tangent dimension
//   State predict(const State&, const Control&) const;                     f(x, u, 0)
//   Covariance process_noise(const State&, const Control&) const;           F_ε Q F_εᵀ + Q_reg
//   State sample(const State&, const Control&, RandomStream&) const;        f(x, u + ε), ε ~ N(0, Q)
//   static State retract(const State&, const Tangent&);                     x ⊕ δ
//   static Tangent local(const State& a, const State& b);                   a ⊖ b   (b ⊕ (a ⊖ b) = a)
//   double log_density(const State& x, const State& x_prev, const Control&) const;  log N(x ⊖ f; 0, P̄)
// For 2D poses ⊕ is addition with θ wrapped to (−π, π]; for SE(3) it is the right perturbation of
// core/lie.hpp.
#include <cmath>

#include <Eigen/Core>

#include "core/gaussian.hpp"
#include "core/lie.hpp"
#include "core/random.hpp"

namespace glmbslam::backend {

using Pose2 = Eigen::Vector3d;  ///< (x, y, θ), θ in (−π, π]

/// Pose helpers for 2D states shared by the 2D motion models.
struct Pose2Manifold {
  static constexpr int kDim = 3;
  using State = Pose2;
  using Tangent = Eigen::Vector3d;
  using Covariance = Eigen::Matrix3d;
  static State retract(const State& x, const Tangent& d) {
    State r = x + d;
    r.z() = wrap_angle(r.z());
    return r;
  }
  static Tangent local(const State& a, const State& b) {
    Tangent d = a - b;
    d.z() = wrap_angle(d.z());
    return d;
  }
};

struct UnicycleMotionConfig {
  double dt = 1.0;                                 ///< time step T (s)
  double sigma_v = 0.8;                            ///< std of the speed noise (m/s)
  double sigma_omega = 0.5 * M_PI / 180.0;         ///< std of the turn-rate noise (rad/s)
  Eigen::Vector3d regulariser{1e-9, 1e-9, 1e-18};  ///< added to the diagonal of F_ε Q F_εᵀ
  /// Euler integration instead of the exact arc: x + vT cos θ, y + vT sin θ, θ + ωT (the phdslam3 benchmark
  /// data are generated this way).
  bool euler = false;
};

class UnicycleMotion : public Pose2Manifold {
 public:
  using Control = Eigen::Vector2d;  ///< (v, ω)
  using ControlJacobian = Eigen::Matrix<double, 3, 2>;

  UnicycleMotion() = default;
  explicit UnicycleMotion(const UnicycleMotionConfig& config) : config_(config) {}
  const UnicycleMotionConfig& config() const { return config_; }

  /// f(x, u): the noise-free motion (Eq. 49), in the form Δ = vT·sinc(ωT/2)·(cos, sin)(θ + ωT/2), which is
  /// numerically stable for every ω (including ω = 0).
  State predict(const State& x, const Control& u) const {
    const double T = config_.dt, v = u(0), b = u(1) * T, a = config_.euler ? x(2) : x(2) + 0.5 * b;
    const double d = config_.euler ? v * T : v * T * sinc(0.5 * b);
    return State(x(0) + d * std::cos(a), x(1) + d * std::sin(a), wrap_angle(x(2) + b));
  }

  /// F_x = ∂f/∂x.
  Covariance jacobian_state(const State& x, const Control& u) const {
    const double T = config_.dt, v = u(0), b = u(1) * T, a = config_.euler ? x(2) : x(2) + 0.5 * b;
    const double d = config_.euler ? v * T : v * T * sinc(0.5 * b);
    Covariance F = Covariance::Identity();
    F(0, 2) = -d * std::sin(a);
    F(1, 2) = d * std::cos(a);
    return F;
  }

  /// F_ε = ∂f/∂u (the control noise is additive on u).
  ControlJacobian jacobian_control(const State& x, const Control& u) const {
    const double T = config_.dt, v = u(0), b = u(1) * T, a = config_.euler ? x(2) : x(2) + 0.5 * b;
    const double s = config_.euler ? 1.0 : sinc(0.5 * b), ds = config_.euler ? 0.0 : sinc_derivative(0.5 * b);
    const double half = config_.euler ? 0.0 : 0.5;  // ∂a/∂ω = half·T
    const double c = std::cos(a), sn = std::sin(a);
    ControlJacobian G;
    G(0, 0) = T * s * c;
    G(1, 0) = T * s * sn;
    G(0, 1) = v * T * T * (0.5 * ds * c - half * s * sn);
    G(1, 1) = v * T * T * (0.5 * ds * sn + half * s * c);
    G(2, 0) = 0.0;
    G(2, 1) = T;
    return G;
  }

  Eigen::Matrix2d control_noise() const {
    return Eigen::Vector2d(config_.sigma_v * config_.sigma_v, config_.sigma_omega * config_.sigma_omega)
        .asDiagonal();
  }

  /// P̄ = F_ε Q F_εᵀ + Q_reg (Eq. 32 with P_x = 0).
  Covariance process_noise(const State& x, const Control& u) const {
    const ControlJacobian G = jacobian_control(x, u);
    Covariance P = G * control_noise() * G.transpose();
    P.diagonal() += config_.regulariser;
    return P;
  }

  /// Draws from the motion model: f(x, u + ε), ε ~ N(0, Q).
  State sample(const State& x, const Control& u, RandomStream& rng) const {
    Control noisy = u;
    noisy(0) += config_.sigma_v * rng.normal();
    noisy(1) += config_.sigma_omega * rng.normal();
    return predict(x, noisy);
  }

  /// log N(x ⊖ f(x_prev, u); 0, P̄): the Gaussian motion density used in the importance weights.
  double log_density(const State& x, const State& x_prev, const Control& u) const {
    return log_gaussian(local(x, predict(x_prev, u)), process_noise(x_prev, u));
  }

 private:
  static double sinc(double t) { return std::abs(t) < 1e-4 ? 1.0 - t * t / 6.0 : std::sin(t) / t; }
  static double sinc_derivative(double t) {
    return std::abs(t) < 1e-4 ? -t / 3.0 : (t * std::cos(t) - std::sin(t)) / (t * t);
  }
  UnicycleMotionConfig config_;
};

}  // namespace glmbslam::backend
