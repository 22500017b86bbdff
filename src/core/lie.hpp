#pragma once
// SO(3)/SE(3)/SE(2) helpers on Eigen.
//
// Convention (used everywhere in the project): a perturbation ξ = (ρ, φ) ∈ ℝ⁶ of a pose T ∈ SE(3) is
// right-multiplied, T ⊕ ξ = T · Exp(ξ), with ρ the translational and φ the rotational part, both expressed
// in the body frame of T. Jacobians "w.r.t. the pose" are w.r.t. ξ at ξ = 0.
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/types.hpp"

namespace glmbslam {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Skew-symmetric matrix [v]× with [v]× w = v × w.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// Exp: so(3) → SO(3) (Rodrigues).
Eigen::Matrix3d so3_exp(const Eigen::Vector3d& phi);
/// Log: SO(3) → so(3), angle in [0, π].
Eigen::Vector3d so3_log(const Eigen::Matrix3d& R);
/// Left Jacobian of SO(3), V in Exp(ξ) = [Exp(φ), V ρ].
Eigen::Matrix3d so3_left_jacobian(const Eigen::Vector3d& phi);
/// Exp: se(3) → SE(3) with ξ = (ρ, φ).
Pose3 se3_exp(const Vector6d& xi);
/// Log: SE(3) → se(3), inverse of se3_exp.
Vector6d se3_log(const Pose3& T);
/// T ⊕ ξ = T · Exp(ξ) (right perturbation).
inline Pose3 se3_plus(const Pose3& T, const Vector6d& xi) {
  return T * se3_exp(xi);
}
/// a ⊖ b = Log(b⁻¹ · a), so that b ⊕ (a ⊖ b) = a.
inline Vector6d se3_minus(const Pose3& a, const Pose3& b) {
  return se3_log(b.inverse() * a);
}
/// Adjoint of T, Ad_T ξ = Log(T Exp(ξ) T⁻¹) to first order, for ξ = (ρ, φ).
Matrix6d se3_adjoint(const Pose3& T);
/// Rotation angle of a rotation matrix in [0, π] from its skew part and trace (atan2): exact near 0 and π and
/// blind to a symmetric deviation from orthonormality. (The KITTI metric keeps the devkit's acos:
/// kitti_metric.)
double rotation_angle(const Eigen::Matrix3d& R);

/// Wraps an angle to (−π, π].
inline double wrap_angle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a <= 0.0) a += 2.0 * M_PI;
  return a - M_PI;
}

}  // namespace glmbslam
