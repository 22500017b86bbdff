#pragma once
// Rectified stereo pinhole model z = π(p) = (u_L, v, u_R), its inverse (triangulation) and their Jacobians.
// Plain Eigen, no OpenCV: shared by the frontend (triangulation, VO) and the backend (3D measurement model).
//
// For a point p = (x, y, z) in the left camera frame, with the right camera at +b along x:
//   u_L = f_x x / z + c_x,   v = f_y y / z + c_y,   u_R = f_x (x − b) / z + c_x.
// Pose Jacobians use the project convention (core/lie.hpp): T ⊕ ξ = T · Exp(ξ), ξ = (ρ, φ).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/lie.hpp"
#include "core/types.hpp"

namespace glmbslam {

using Matrix36d = Eigen::Matrix<double, 3, 6>;

struct StereoCamera {
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  double baseline = 0.0;  ///< metres, > 0

  StereoCamera() = default;
  StereoCamera(double fx_, double fy_, double cx_, double cy_, double b)
      : fx(fx_), fy(fy_), cx(cx_), cy(cy_), baseline(b) {}
  explicit StereoCamera(const StereoCalibration& c)
      : fx(c.fx), fy(c.fy), cx(c.cx), cy(c.cy), baseline(c.baseline) {}

  /// f_x · b: disparity (pixels) times depth (metres).
  double bf() const { return fx * baseline; }

  /// z = π(p) for p in the left camera frame (p.z() must be > 0).
  Eigen::Vector3d project(const Eigen::Vector3d& p) const {
    const double iz = 1.0 / p.z();
    return {fx * p.x() * iz + cx, fy * p.y() * iz + cy, fx * (p.x() - baseline) * iz + cx};
  }

  /// ∂π/∂p at p.
  Eigen::Matrix3d project_jacobian(const Eigen::Vector3d& p) const {
    const double iz = 1.0 / p.z();
    const double iz2 = iz * iz;
    Eigen::Matrix3d J;
    J << fx * iz, 0.0, -fx * p.x() * iz2,  //
        0.0, fy * iz, -fy * p.y() * iz2,   //
        fx * iz, 0.0, -fx * (p.x() - baseline) * iz2;
    return J;
  }

  /// Triangulation p = π⁻¹(z); requires a positive disparity u_L − u_R.
  Eigen::Vector3d triangulate(const Eigen::Vector3d& z) const {
    const double depth = bf() / (z.x() - z.z());
    return {(z.x() - cx) * depth / fx, (z.y() - cy) * depth / fy, depth};
  }

  /// ∂π⁻¹/∂z at z (equals the inverse of project_jacobian at the triangulated point).
  Eigen::Matrix3d triangulate_jacobian(const Eigen::Vector3d& z) const {
    const double d = z.x() - z.z();
    const double b = baseline;
    const double id2 = 1.0 / (d * d);
    const double s = fx / fy;
    Eigen::Matrix3d J;
    J << b * (cx - z.z()) * id2, 0.0, b * (z.x() - cx) * id2,                //
        -s * b * (z.y() - cy) * id2, s * b / d, s * b * (z.y() - cy) * id2,  //
        -fx * b * id2, 0.0, fx * b * id2;
    return J;
  }

  /// Covariance of the triangulated point for isotropic pixel noise σ on each coordinate of z.
  Eigen::Matrix3d triangulation_covariance(const Eigen::Vector3d& z, double sigma) const {
    const Eigen::Matrix3d J = triangulate_jacobian(z);
    return sigma * sigma * J * J.transpose();
  }

  /// Projection of a world point m seen from a camera at pose T_wc: z = π(T_wc⁻¹ m).
  /// Optionally returns ∂z/∂ξ (3×6, right perturbation T_wc · Exp(ξ)) and ∂z/∂m (3×3).
  /// With p = T_wc⁻¹ m: ∂p/∂ρ = −I, ∂p/∂φ = [p]×, ∂p/∂m = Rᵀ.
  Eigen::Vector3d project_from_pose(const Pose3& T_wc, const Eigen::Vector3d& m, Matrix36d* J_pose = nullptr,
                                    Eigen::Matrix3d* J_point = nullptr) const {
    const Eigen::Matrix3d Rt = T_wc.linear().transpose();
    const Eigen::Vector3d p = Rt * (m - T_wc.translation());
    if (J_pose != nullptr || J_point != nullptr) {
      const Eigen::Matrix3d Jp = project_jacobian(p);
      if (J_pose != nullptr) {
        J_pose->leftCols<3>() = -Jp;
        J_pose->rightCols<3>() = Jp * skew(p);
      }
      if (J_point != nullptr) *J_point = Jp * Rt;
    }
    return project(p);
  }
};

}  // namespace glmbslam
