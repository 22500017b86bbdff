#pragma once
// Two-view stereo bundle adjustment for the relative pose (Ceres): points tracked from a reference frame
// (where they were triangulated) into the current frame. Unknowns: T_ref_cur ∈ SE(3) (right perturbation, see
// se3_manifold.hpp) and each point in the reference frame. Residuals, whitened by the pixel σ of each
// keypoint:
//   reference: π(X) − z_ref (u_L, v, u_R),   current: π(T_ref_cur⁻¹ X) − z_cur (u_L, v, u_R, or u_L, v only),
// with a Huber loss; between rounds, observations whose χ² exceeds the gate are dropped. The covariance of
// the pose is the inverse of the Schur complement of the Gauss–Newton information (points marginalised) at
// the solution, in the right-perturbation tangent of T_ref_cur: T_true ≈ T̂ · Exp(ξ), ξ ~ N(0, Q).
#include <vector>

#include "core/lie.hpp"
#include "frontend/stereo_projection.hpp"

namespace glmbslam::frontend {

struct TrackedPoint {
  Eigen::Vector3d point_ref = Eigen::Vector3d::Zero();  ///< initial 3D point in the reference frame
  Eigen::Vector3d z_ref = Eigen::Vector3d::Zero();      ///< stereo measurement in the reference frame
  double sigma_ref = 1.0;
  Eigen::Vector3d z_cur = Eigen::Vector3d::Zero();  ///< measurement in the current frame (u_R unused if mono)
  double sigma_cur = 1.0;
  bool cur_stereo = true;  ///< false: only (u_L, v) of z_cur is observed
};

struct PoseRefinementOptions {
  double huber_delta = 2.0;       ///< Huber threshold on the whitened residual norm
  double chi2_threshold = 7.815;  ///< 3-dof gate; the 2-dof gate is scaled by 5.991 / 7.815
  int rounds = 2;
  int max_iterations = 10;
};

struct PoseRefinementResult {
  Pose3 T_ref_cur = Pose3::Identity();
  Matrix6d covariance = Matrix6d::Identity();
  std::vector<char> inlier;  ///< per tracked point (1 = kept in the last round)
  int inliers = 0;
  bool success = false;  ///< false if too few points or a degenerate information matrix
};

PoseRefinementResult refine_stereo_pose(const StereoCamera& camera, const std::vector<TrackedPoint>& points,
                                        const Pose3& initial_T_ref_cur, const PoseRefinementOptions& options);

}  // namespace glmbslam::frontend
