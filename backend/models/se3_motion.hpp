#pragma once
// SE(3) motion driven by visual odometry (issue 7): the control is the relative pose u_k = T_{k−1,k} measured
// by the stereo frontend with its covariance Q_k (6×6, tangent ξ = (ρ, φ) of core/lie.hpp), so
//
//   x_k = x_{k−1} · u_k · Exp(ε),   ε ~ N(0, s·Q_k)        (paper 000 Eq. 31 with f = composition)
//
// where s ≥ 1 inflates the frontend's covariance (configurable). Implements the MotionModel concept of
// unicycle_motion.hpp with State = Pose3 (T_world_camera) and ⊕ the right perturbation.
#include <Eigen/Core>

#include "core/gaussian.hpp"
#include "core/lie.hpp"
#include "core/random.hpp"
#include "core/types.hpp"

namespace glmbslam::backend {

struct Se3MotionConfig {
  double covariance_inflation = 1.0;    ///< s: multiplies the frontend's Q_k
  double min_sigma_translation = 1e-3;  ///< floor on each translational std (m) so Q is never singular
  double min_sigma_rotation = 1e-4;     ///< floor on each rotational std (rad)
};

/// One step of visual odometry: relative pose T_{k−1,k} and its covariance.
struct RelativePoseControl {
  Pose3 delta = Pose3::Identity();
  Matrix6d covariance = Matrix6d::Identity() * 1e-4;
  bool allFinite() const { return delta.matrix().allFinite() && covariance.allFinite(); }
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

class Se3Motion {
 public:
  static constexpr int kDim = 6;
  using State = Pose3;
  using Tangent = Vector6d;
  using Covariance = Matrix6d;
  using Control = RelativePoseControl;

  Se3Motion() = default;
  explicit Se3Motion(const Se3MotionConfig& config) : config_(config) {}
  const Se3MotionConfig& config() const { return config_; }

  State predict(const State& x, const Control& u) const { return x * u.delta; }

  /// s·Q_k with the floors applied to the diagonal (the noise is already in the tangent of the prediction).
  Covariance process_noise(const State& /*x*/, const Control& u) const {
    Covariance P = config_.covariance_inflation * u.covariance;
    symmetrize(P);
    const double t2 = config_.min_sigma_translation * config_.min_sigma_translation;
    const double r2 = config_.min_sigma_rotation * config_.min_sigma_rotation;
    for (int i = 0; i < 3; ++i) P(i, i) = std::max(P(i, i), t2);
    for (int i = 3; i < 6; ++i) P(i, i) = std::max(P(i, i), r2);
    return P;
  }

  State sample(const State& x, const Control& u, RandomStream& rng) const {
    const Tangent eps = rng.gaussian<6>(Tangent::Zero(), process_noise(x, u));
    return retract(predict(x, u), eps);
  }

  static State retract(const State& x, const Tangent& d) { return se3_plus(x, d); }
  static Tangent local(const State& a, const State& b) { return se3_minus(a, b); }

  double log_density(const State& x, const State& x_prev, const Control& u) const {
    return log_gaussian(local(x, predict(x_prev, u)), process_noise(x_prev, u));
  }

 private:
  Se3MotionConfig config_;
};

}  // namespace glmbslam::backend
