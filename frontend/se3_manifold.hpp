#pragma once
// ceres::Manifold for a pose T ∈ SE(3) stored as 7 numbers [q_x, q_y, q_z, q_w, t_x, t_y, t_z] (Eigen
// quaternion coefficient order, then translation), with the project's right perturbation T ⊕ ξ = T · Exp(ξ),
// ξ = (ρ, φ).
//
// The cost functions of this folder give their Jacobians directly w.r.t. ξ in the first six columns of the
// 7-column "ambient" Jacobian (last column zero), so PlusJacobian is [I₆; 0] and Ceres' product
// J_ambient · PlusJacobian is exactly ∂r/∂ξ. Only use this manifold with cost functions written that way.
#include <ceres/manifold.h>

#include "core/lie.hpp"

namespace glmbslam::frontend {

/// Packs T into the 7-number block.
void pose_to_block(const Pose3& T, double* block);
/// Unpacks the 7-number block (the quaternion is normalised).
Pose3 block_to_pose(const double* block);

class Se3RightManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace glmbslam::frontend
