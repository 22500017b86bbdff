#include "frontend/se3_manifold.hpp"

#include <Eigen/Core>

namespace glmbslam::frontend {

void pose_to_block(const Pose3& T, double* block) {
  const Eigen::Quaterniond q(T.linear());
  block[0] = q.x();
  block[1] = q.y();
  block[2] = q.z();
  block[3] = q.w();
  block[4] = T.translation().x();
  block[5] = T.translation().y();
  block[6] = T.translation().z();
}

Pose3 block_to_pose(const double* block) {
  Eigen::Quaterniond q(block[3], block[0], block[1], block[2]);
  q.normalize();
  Pose3 T = Pose3::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = Eigen::Vector3d(block[4], block[5], block[6]);
  return T;
}

bool Se3RightManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Vector6d xi = Eigen::Map<const Vector6d>(delta);
  pose_to_block(se3_plus(block_to_pose(x), xi), x_plus_delta);
  return true;
}

bool Se3RightManifold::PlusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topRows<6>().setIdentity();
  return true;
}

bool Se3RightManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<Vector6d> out(y_minus_x);
  out = se3_minus(block_to_pose(y), block_to_pose(x));
  return true;
}

bool Se3RightManifold::MinusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.leftCols<6>().setIdentity();
  return true;
}

}  // namespace glmbslam::frontend
