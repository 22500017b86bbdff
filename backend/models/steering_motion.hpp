#pragma once
// 2D steering-angle ("bicycle") motion model of the EKF-SLAM simulator family used by paper 000's simulations
// (control = speed v and steering angle G, noise σ_v and σ_steer): with wheel base L and time step T,
//
//   f(x, u) = [x + vT cos(θ + G),  y + vT sin(θ + G),  θ + vT sin(G) / L]ᵀ.
//
// Same MotionModel concept as UnicycleMotion (see unicycle_motion.hpp).
#include <cmath>

#include "backend/models/unicycle_motion.hpp"

namespace glmbslam::backend {

struct SteeringMotionConfig {
  double dt = 0.1;                          ///< time step T (s)
  double wheel_base = 0.5;                  ///< L (m)
  double sigma_v = 0.1;                     ///< std of the speed noise (m/s)
  double sigma_steer = 2.0 * M_PI / 180.0;  ///< std of the steering-angle noise (rad)
  Eigen::Vector3d regulariser{1e-9, 1e-9, 1e-18};
};

class SteeringMotion : public Pose2Manifold {
 public:
  using Control = Eigen::Vector2d;  ///< (v, G)
  using ControlJacobian = Eigen::Matrix<double, 3, 2>;

  SteeringMotion() = default;
  explicit SteeringMotion(const SteeringMotionConfig& config) : config_(config) {}
  const SteeringMotionConfig& config() const { return config_; }

  State predict(const State& x, const Control& u) const {
    const double T = config_.dt, v = u(0), g = u(1);
    State r;
    r << x(0) + v * T * std::cos(x(2) + g), x(1) + v * T * std::sin(x(2) + g),
        wrap_angle(x(2) + v * T * std::sin(g) / config_.wheel_base);
    return r;
  }

  Covariance jacobian_state(const State& x, const Control& u) const {
    const double T = config_.dt, v = u(0), g = u(1);
    Covariance F = Covariance::Identity();
    F(0, 2) = -v * T * std::sin(x(2) + g);
    F(1, 2) = v * T * std::cos(x(2) + g);
    return F;
  }

  ControlJacobian jacobian_control(const State& x, const Control& u) const {
    const double T = config_.dt, v = u(0), g = u(1), L = config_.wheel_base;
    ControlJacobian G;
    G << T * std::cos(x(2) + g), -v * T * std::sin(x(2) + g),  //
        T * std::sin(x(2) + g), v * T * std::cos(x(2) + g),    //
        T * std::sin(g) / L, v * T * std::cos(g) / L;
    return G;
  }

  Eigen::Matrix2d control_noise() const {
    return Eigen::Vector2d(config_.sigma_v * config_.sigma_v, config_.sigma_steer * config_.sigma_steer)
        .asDiagonal();
  }

  Covariance process_noise(const State& x, const Control& u) const {
    const ControlJacobian G = jacobian_control(x, u);
    Covariance P = G * control_noise() * G.transpose();
    P.diagonal() += config_.regulariser;
    return P;
  }

  State sample(const State& x, const Control& u, RandomStream& rng) const {
    Control noisy = u;
    noisy(0) += config_.sigma_v * rng.normal();
    noisy(1) += config_.sigma_steer * rng.normal();
    return predict(x, noisy);
  }

  double log_density(const State& x, const State& x_prev, const Control& u) const {
    return log_gaussian(local(x, predict(x_prev, u)), process_noise(x_prev, u));
  }

 private:
  SteeringMotionConfig config_;
};

}  // namespace glmbslam::backend
