#pragma once
// Ceres factors of the 2D M-step (digest 3.5 option B): the SE(2) pose manifold, the motion factor of the
// odometry (paper 004 Eq. 2, whitened by the process covariance of the motion model) and the
// responsibility-weighted measurement factor √β · R^{-1/2} (z − ẑ(x, m)) (Eq. 3 weighted by the E-step's β).
#include <cmath>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "backend/mlslam/mlslam_config.hpp"
#include "backend/mlslam/smooth_detection.hpp"
#include "core/lie.hpp"

namespace glmbslam::backend {

/// (x, y, θ) with x ⊕ δ = (x + δ_x, y + δ_y, wrap(θ + δ_θ)): the 2D poses' convention (Pose2Manifold).
class Pose2CeresManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    x_plus_delta[0] = x[0] + delta[0];
    x_plus_delta[1] = x[1] + delta[1];
    x_plus_delta[2] = wrap_angle(x[2] + delta[2]);
    return true;
  }
  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(jacobian).setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    y_minus_x[0] = y[0] - x[0];
    y_minus_x[1] = y[1] - x[1];
    y_minus_x[2] = wrap_angle(y[2] - x[2]);
    return true;
  }
  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(jacobian).setIdentity();
    return true;
  }
};

/// Inverse of the lower Cholesky factor of a covariance: W with Wᵀ W = S^{-1}.
template <class Matrix>
typename Matrix::PlainObject whitening(const Matrix& S) {
  using Plain = typename Matrix::PlainObject;
  const Eigen::LLT<Plain> llt(S);
  return llt.matrixL().solve(Plain::Identity(S.rows(), S.cols()));
}

/// The motion factor of x_{i−1} → x_i (paper 004 Eq. 2): r = W_L (R(θ_{i−1})ᵀ ⊙ (x_i ⊖ f(x_{i−1}, u))), the
/// residual rotated into the frame of x_{i−1} (position part; the heading part is unchanged) and whitened by
/// W_L, Wᵀ_L W_L = R(θ)ᵀ P̄(x_{i−1}, u)⁻¹ R(θ). ‖r‖² = −2 log g − log det(2π P̄) exactly, since the unicycle,
/// steering and Ackermann models are rotation-equivariant: P̄ = R(θ) P̄_0(u) R(θ)ᵀ plus a regulariser
/// isotropic in x, y, so W_L depends on u alone and holding it through the solve is exact at every heading.
/// The world-frame form with P̄ re-factorised at each evaluation is the same cost, but its numeric
/// derivatives are not: P̄ has almost no lateral variance (regulariser 1e-9 m², condition ~10⁹), the
/// factorisation loses most digits of the lateral row, and the Jacobians it gave stalled the solver along
/// the trajectory's slow rotation modes (docs/investigations.md, "phdslam3: the motion factor in the
/// previous pose's frame").
template <class Motion>
struct MotionResidual {
  const Motion* motion;
  typename Motion::Control u;
  Eigen::Matrix3d W_local;
  bool operator()(const double* prev, const double* cur, double* r) const {
    const typename Motion::State a(prev[0], prev[1], prev[2]), b(cur[0], cur[1], cur[2]);
    Eigen::Vector3d d = Motion::local(b, motion->predict(a, u));
    const double c = std::cos(a(2)), s = std::sin(a(2));
    d.head<2>() = Eigen::Vector2d(c * d(0) + s * d(1), -s * d(0) + c * d(1));
    Eigen::Map<Eigen::Vector3d> residual(r);
    residual = W_local * d;
    return true;
  }
};

/// The motion factor of x_{i−1} → x_i from W, the whitening of P̄ at the linearisation pose
/// `prev`: W_L = W · blockdiag(R(θ_prev), 1) (MotionResidual).
template <class Motion>
ceres::CostFunction* make_motion_factor(const Motion& motion, const typename Motion::Control& u,
                                        const typename Motion::Covariance& W,
                                        const typename Motion::State& prev) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(prev(2)).toRotationMatrix();
  return new ceres::NumericDiffCostFunction<MotionResidual<Motion>, ceres::CENTRAL, 3, 3, 3>(
      new MotionResidual<Motion>{&motion, u, W * R});
}

/// r = √β W (z − ẑ(x, m)) with the model's analytic Jacobians (H_x is w.r.t. the pose tangent, which is the
/// additive one of Pose2CeresManifold).
template <class Model>
class WeightedMeasurementFactor
    : public ceres::SizedCostFunction<Model::kMeasDim, Model::kPoseDim, Model::kLandmarkDim> {
 public:
  WeightedMeasurementFactor(const Model& model, const typename Model::Measurement& z,
                            const typename Model::MeasurementCovariance& W, double beta)
      : model_(model), z_(z), W_(std::sqrt(beta) * W) {}
  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const typename Model::Pose x = Eigen::Map<const typename Model::Pose>(p[0]);
    const typename Model::Landmark m = Eigen::Map<const typename Model::Landmark>(p[1]);
    typename Model::PoseJacobian Hx;
    typename Model::LandmarkJacobian Hm;
    const auto zhat = model_.linearize(x, m, &Hx, &Hm);
    Eigen::Map<typename Model::Measurement> r(residuals);
    r = W_ * model_.residual(z_, zhat);
    if (jacobians != nullptr) {
      using JacX = Eigen::Matrix<double, Model::kMeasDim, Model::kPoseDim, Eigen::RowMajor>;
      using JacM = Eigen::Matrix<double, Model::kMeasDim, Model::kLandmarkDim, Eigen::RowMajor>;
      if (jacobians[0] != nullptr) {
        Eigen::Map<JacX> J(jacobians[0]);
        J = -W_ * Hx;
      }
      if (jacobians[1] != nullptr) {
        Eigen::Map<JacM> J(jacobians[1]);
        J = -W_ * Hm;
      }
    }
    return true;
  }

 private:
  const Model& model_;
  typename Model::Measurement z_;
  typename Model::MeasurementCovariance W_;
};

/// The 2D parts of RfsMlSlam (rfs_ml_slam.hpp): (x, y, θ) poses are their own Ceres blocks on
/// Pose2CeresManifold, the motion factor by numeric derivatives, the measurement factor analytic, p_D smooth
/// in range and bearing; the default birth and merge distances are multiples of σ_r.
template <class Motion, class Model>
struct PlanarMlSlamParts {
  using Pose = typename Model::Pose;
  using Detection = SmoothDetection2D;
  using Manifold = Pose2CeresManifold;
  static constexpr int kBlockSize = 3;
  static Detection detection(const Model& model, const MlSlamConfig& c) {
    return Detection(model, c.border_range_m, c.border_bearing_rad);
  }
  static double length_scale(const Model& model) { return std::sqrt(model.noise()(0, 0)); }
  static void to_block(const Pose& x, double* block) { Eigen::Map<Eigen::Vector3d>{block} = x; }
  static Pose from_block(const double* block) {
    Pose x = Eigen::Map<const Eigen::Vector3d>(block);
    x(2) = wrap_angle(x(2));
    return x;
  }
  static ceres::CostFunction* motion_factor(const Motion& motion, const typename Motion::Control& u,
                                            const typename Motion::Covariance& W, const Pose& prev,
                                            double /*scale*/) {
    // the configured P̄, not the M-step's s·P̄ (MlSlamConfig::motion_noise "estimated" rescales the E-step's
    // log g only: applied in the 2D M-step too, s collapses to its lower bound on the solver tests)
    return make_motion_factor(motion, u, W, prev);
  }
  static ceres::CostFunction* measurement_factor(const Model& model, const typename Model::Measurement& z,
                                                 const typename Model::MeasurementCovariance& W,
                                                 double beta) {
    return new WeightedMeasurementFactor<Model>(model, z, W, beta);
  }
};

}  // namespace glmbslam::backend
