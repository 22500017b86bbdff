#pragma once
// Ceres factors of the stereo M-step (digest 3.5 option B): SE(3) pose blocks, the relative-pose (VO control)
// factor W (x_i ⊖ x_{i−1} u_i) (paper 004 Eq. 2 with the SE(3) motion of backend/models/se3_motion.hpp) and
// the responsibility-weighted stereo measurement factor √β R^{-1/2} (z − π(x⁻¹ m)) (Eq. 3 weighted by the
// E-step's β; the projection of core/stereo_camera.hpp). The motion factor has automatic derivatives through
// the quaternion, the measurement factor (one per gated pair: the hot one) analytic ones.
//
// Pose block (7 doubles): the unit quaternion of R_wc in Eigen's order (x, y, z, w), then t_wc; its manifold
// is Ceres' EigenQuaternionManifold × EuclideanManifold<3>.
#include <cmath>

#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/rotation.h>
#include <ceres/sized_cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/stereo_camera.hpp"
#include "core/types.hpp"

namespace glmbslam::backend {

constexpr int kPose3BlockSize = 7;
using Pose3CeresManifold =
    ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>>;

inline void pose3_to_block(const Pose3& T, double* block) {
  Eigen::Map<Eigen::Quaterniond>{block} = Eigen::Quaterniond(T.linear()).normalized();
  Eigen::Map<Eigen::Vector3d>{block + 4} = T.translation();
}

inline Pose3 pose3_from_block(const double* block) {
  Pose3 T = Pose3::Identity();
  T.linear() = Eigen::Map<const Eigen::Quaterniond>(block).normalized().toRotationMatrix();
  T.translation() = Eigen::Map<const Eigen::Vector3d>(block + 4);
  return T;
}

/// ξ = Log(T) = (ρ, φ) of core/lie.hpp (se3_log) for T = (q, t): φ from the quaternion, ρ = V(φ)⁻¹ t with
/// V⁻¹ = I − ½[φ]× + c [φ]×², c = (1 − θ/(2 tan(θ/2))) / θ² (series below θ² = 1e-6).
template <typename T>
Eigen::Matrix<T, 6, 1> se3_log_of(const Eigen::Quaternion<T>& q, const Eigen::Matrix<T, 3, 1>& t) {
  const T wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
  Eigen::Matrix<T, 3, 1> phi;
  ceres::QuaternionToAngleAxis(wxyz, phi.data());
  const T theta2 = phi.squaredNorm();
  T c;
  if (theta2 < T(1e-6)) {
    c = T(1.0 / 12.0) + theta2 / T(720.0);
  } else {
    const T theta = sqrt(theta2);
    c = (T(1.0) - theta / (T(2.0) * tan(theta / T(2.0)))) / theta2;
  }
  const Eigen::Matrix<T, 3, 1> pxt = phi.cross(t);
  Eigen::Matrix<T, 6, 1> xi;
  xi.template head<3>() = t - T(0.5) * pxt + c * phi.cross(pxt);
  xi.template tail<3>() = phi;
  return xi;
}

/// r = W Log((x_{i−1} u)⁻¹ x_i) = W (x_i ⊖ f(x_{i−1}, u)), the whitened SE(3) motion residual.
struct RelativePoseResidual {
  Eigen::Quaterniond q_u;
  Eigen::Vector3d t_u;
  Matrix6d W;
  template <typename T>
  bool operator()(const T* prev, const T* cur, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(prev), q_b(cur);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_a(prev + 4), t_b(cur + 4);
    const Eigen::Quaternion<T> q_pred = q_a * q_u.cast<T>();
    const Eigen::Matrix<T, 3, 1> t_pred = t_a + q_a * t_u.cast<T>();
    const Eigen::Quaternion<T> q_inv = q_pred.conjugate();
    const Eigen::Quaternion<T> q_err = q_inv * q_b;
    const Eigen::Matrix<T, 3, 1> t_err = q_inv * (t_b - t_pred);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual);
    r = W.cast<T>() * se3_log_of(q_err, t_err);
    return true;
  }
};

/// The motion factor of one VO control: relative pose u (T_{i−1,i}) and whitening W (Wᵀ W = Q⁻¹).
inline ceres::CostFunction* make_relative_pose_factor(const Pose3& u, const Matrix6d& W) {
  return new ceres::AutoDiffCostFunction<RelativePoseResidual, 6, kPose3BlockSize, kPose3BlockSize>(
      new RelativePoseResidual{Eigen::Quaterniond(u.linear()).normalized(), u.translation(), W});
}

/// r = W (z − π(x⁻¹ m)) with W = √β R^{-1/2}; z = (u_L, v, u_R).
struct StereoProjectionResidual {
  StereoCamera camera;
  Eigen::Vector3d z;
  Eigen::Matrix3d W;
  template <typename T>
  bool operator()(const T* pose, const T* landmark, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(pose);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(pose + 4), m(landmark);
    const Eigen::Matrix<T, 3, 1> p = q.conjugate() * (m - t);
    const T iz = T(1.0) / p.z();
    Eigen::Matrix<T, 3, 1> zhat;
    zhat << T(camera.fx) * p.x() * iz + T(camera.cx), T(camera.fy) * p.y() * iz + T(camera.cy),
        T(camera.fx) * (p.x() - T(camera.baseline)) * iz + T(camera.cx);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = W.cast<T>() * (z.cast<T>() - zhat);
    return true;
  }
};

/// r = W (z − π(x⁻¹ m)) and, where `jacobians` asks for them, its analytic Jacobians (below); `parameters`
/// are the pose block and the landmark, as Ceres hands them to CostFunction::Evaluate.
inline void evaluate_stereo_projection(const StereoCamera& camera, const Eigen::Vector3d& z,
                                       const Eigen::Matrix3d& W, double const* const* parameters,
                                       double* residuals, double** jacobians) {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 4), m(parameters[1]);
  const Eigen::Vector3d v = m - t;
  const Eigen::Vector3d p = q.conjugate() * v;
  const double iz = 1.0 / p.z();
  const double fx = camera.fx, fy = camera.fy;
  const Eigen::Vector3d zhat(fx * p.x() * iz + camera.cx, fy * p.y() * iz + camera.cy,
                             fx * (p.x() - camera.baseline) * iz + camera.cx);
  Eigen::Map<Eigen::Vector3d>{residuals} = W * (z - zhat);
  if (jacobians == nullptr) return;
  Eigen::Matrix3d dpi;  // ∂π/∂p
  dpi << fx * iz, 0.0, -fx * p.x() * iz * iz, 0.0, fy * iz, -fy * p.y() * iz * iz, fx * iz, 0.0,
      -fx * (p.x() - camera.baseline) * iz * iz;
  const Eigen::Matrix3d dr_dp = -W * dpi;
  const Eigen::Matrix3d Rt = q.toRotationMatrix().transpose();
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 3, kPose3BlockSize, Eigen::RowMajor>> J(jacobians[0]);
    const Eigen::Vector3d u = q.vec();
    const double w = q.w();
    Eigen::Matrix3d v_cross;
    v_cross << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
    const Eigen::Matrix3d dp_du = 2.0 * u.dot(v) * Eigen::Matrix3d::Identity() + 2.0 * u * v.transpose() -
                                  2.0 * v * u.transpose() + 2.0 * w * v_cross;
    const Eigen::Vector3d dp_dw = 2.0 * w * v - 2.0 * u.cross(v);
    J.block<3, 3>(0, 0) = dr_dp * dp_du;
    J.col(3) = dr_dp * dp_dw;
    J.block<3, 3>(0, 4) = -dr_dp * Rt;
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J(jacobians[1]);
    J = dr_dp * Rt;
  }
}

/// StereoProjectionResidual with analytic Jacobians (the M-step's hot factor: one per gated pair of every
/// scan). With v = m − t, p = Rᵀ v, R = R(q) = (w² − ‖u‖²) I + 2 u uᵀ + 2 w [u]× for q = (u, w):
///   ∂r/∂p = −W ∂π/∂p,  ∂p/∂t = −Rᵀ,  ∂p/∂m = Rᵀ,
///   ∂p/∂u = 2 (uᵀv) I + 2 u vᵀ − 2 v uᵀ + 2 w [v]×,  ∂p/∂w = 2 w v − 2 u × v
/// (derivatives of the homogeneous form of Rᵀ v; on the unit sphere, where the manifold's tangent lies, they
/// equal those of Eigen's rotation of the automatic version).
class StereoProjectionFactor : public ceres::SizedCostFunction<3, kPose3BlockSize, 3> {
 public:
  StereoProjectionFactor(const StereoCamera& camera, const Eigen::Vector3d& z, const Eigen::Matrix3d& W)
      : camera_(camera), z_(z), W_(W) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    evaluate_stereo_projection(camera_, z_, W_, parameters, residuals, jacobians);
    return true;
  }

 private:
  StereoCamera camera_;
  Eigen::Vector3d z_;
  Eigen::Matrix3d W_;
};

/// What the pair factors of one M-step problem share: the camera and R^{-1/2}.
struct StereoFactorContext {
  StereoCamera camera;
  Eigen::Matrix3d W_R;
};

/// The measurement factor of one (pose, landmark) pair with its β-weighted measurements merged (the M-step
/// objective of paper 004 Eq. 18, summed over the pair's measurements n):
///   Σ_n β_n ‖W_R (z_n − ẑ)‖² = B ‖W_R (z̄ − ẑ)‖² + Σ_n β_n ‖W_R (z_n − z̄)‖²,  B = Σ_n β_n, z̄ = Σ_n β_n z_n /
///   B.
/// The last term depends on neither the pose nor the landmark: the same minimiser, gradient and Gauss–Newton
/// matrix as one StereoProjectionFactor per measurement. The weights are set between Ceres solves, so one
/// problem serves every EM round (B = 0: the pair contributes nothing this round).
class StereoPairFactor : public ceres::SizedCostFunction<3, kPose3BlockSize, 3> {
 public:
  explicit StereoPairFactor(const StereoFactorContext* context) : context_(context) {}

  /// z̄ and B of this round.
  void set(const Eigen::Vector3d& z_bar, double weight) {
    z_bar_ = z_bar;
    sqrt_weight_ = std::sqrt(weight);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    evaluate_stereo_projection(context_->camera, z_bar_, sqrt_weight_ * context_->W_R, parameters, residuals,
                               jacobians);
    return true;
  }

 private:
  const StereoFactorContext* context_;
  Eigen::Vector3d z_bar_ = Eigen::Vector3d::Zero();
  double sqrt_weight_ = 0.0;
};

/// The M-step's measurement factor (analytic Jacobians).
inline ceres::CostFunction* make_stereo_measurement_factor(const StereoCamera& camera,
                                                           const Eigen::Vector3d& z, const Eigen::Matrix3d& W,
                                                           double beta) {
  return new StereoProjectionFactor(camera, z, std::sqrt(beta) * W);
}

/// The same factor with automatic derivatives (the reference of the analytic one in the tests).
inline ceres::CostFunction* make_stereo_measurement_factor_autodiff(const StereoCamera& camera,
                                                                    const Eigen::Vector3d& z,
                                                                    const Eigen::Matrix3d& W, double beta) {
  return new ceres::AutoDiffCostFunction<StereoProjectionResidual, 3, kPose3BlockSize, 3>(
      new StereoProjectionResidual{camera, z, std::sqrt(beta) * W});
}

}  // namespace glmbslam::backend
