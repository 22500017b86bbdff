#include "core/lie.hpp"

#include <cmath>

namespace glmbslam {

Eigen::Matrix3d so3_exp(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  if (theta < 1e-10) {
    return Eigen::Matrix3d::Identity() + skew(phi);
  }
  return Eigen::AngleAxisd(theta, phi / theta).toRotationMatrix();
}

Eigen::Vector3d so3_log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  double angle = aa.angle();
  Eigen::Vector3d axis = aa.axis();
  if (angle > M_PI) {
    angle = 2.0 * M_PI - angle;
    axis = -axis;
  }
  return axis * angle;
}

Eigen::Matrix3d so3_left_jacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d K = skew(phi);
  if (theta < 1e-6) {
    return Eigen::Matrix3d::Identity() + 0.5 * K + K * K / 6.0;
  }
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * K +
         (theta - std::sin(theta)) / (t2 * theta) * K * K;
}

Pose3 se3_exp(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  Pose3 T = Pose3::Identity();
  T.linear() = so3_exp(phi);
  T.translation() = so3_left_jacobian(phi) * rho;
  return T;
}

Vector6d se3_log(const Pose3& T) {
  const Eigen::Vector3d phi = so3_log(T.linear());
  Vector6d xi;
  xi.head<3>() = so3_left_jacobian(phi).inverse() * T.translation();
  xi.tail<3>() = phi;
  return xi;
}

Matrix6d se3_adjoint(const Pose3& T) {
  Matrix6d ad = Matrix6d::Zero();
  const Eigen::Matrix3d R = T.linear();
  ad.topLeftCorner<3, 3>() = R;
  ad.topRightCorner<3, 3>() = skew(T.translation()) * R;
  ad.bottomRightCorner<3, 3>() = R;
  return ad;
}

double rotation_angle(const Eigen::Matrix3d& R) {
  // R − Rᵀ = 2 sin θ [k]×, trace R = 1 + 2 cos θ. atan2 keeps full precision near 0 and π, where acos of the
  // trace alone resolves only ~√ε, and a symmetric deviation from orthonormality (rotations written with six
  // digits, as in KITTI pose files, RᵀR ≠ I) adds no angle.
  const Eigen::Vector3d axis(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * axis.norm(), 0.5 * (R.trace() - 1.0));
}

}  // namespace glmbslam
