#pragma once
// Motion-only refinement of the relative pose T_ref_cur ∈ SE(3) from points tracked from a reference frame
// (where they were triangulated from stereo) into the current frame. The points stay fixed; the uncertainty
// of each triangulation is folded into the weighting of its residual, which marginalises the point of the
// two-view stereo bundle adjustment to first order:
//   e_i = π(T_ref_cur⁻¹ X_i) − z_cur,i   (u_L, v, u_R; or u_L, v when the current keypoint has no stereo
//   match) S_i = σ_cur,i² I + J_X Σ_X,i J_Xᵀ,   Σ_X,i = triangulation covariance of z_ref,i with σ_ref,i,
// minimising Σ ρ(e_iᵀ S_i⁻¹ e_i) with the Huber ρ over the 6 pose parameters (right perturbation
// T ⊕ ξ = T · Exp(ξ), ξ = (ρ, φ), core/lie.hpp). S_i is evaluated at the current pose and held fixed in the
// Jacobian (∂S_i/∂ξ neglected). Two solvers of the same objective:
//  - kCeres: a ceres::Problem with the pose on the SE(3) manifold (se3_manifold.hpp), one analytic cost per
//    point with the whitened residual L_i⁻¹ e_i (S_i = L_i L_iᵀ) and ceres::HuberLoss, Levenberg–Marquardt
//    with a dense normal-equations solver;
//  - kGaussNewton: hand-written Gauss–Newton with Huber weights (IRLS) and step halving if the cost rises.
// Between rounds, points whose χ² exceeds the gate are dropped. The covariance of the pose is the inverse
// Gauss–Newton information Σ w_i J_iᵀ S_i⁻¹ J_i at the solution (Huber weights w_i = ρ'; for kCeres this is
// JᵀJ of the robustified whitened Jacobian Ceres evaluates at the solution), in the right-perturbation
// tangent of T_ref_cur: T_true ≈ T̂ · Exp(ξ), ξ ~ N(0, Q).
#include <string>
#include <vector>

#include "core/lie.hpp"
#include "frontend/frontend_config.hpp"
#include "frontend/stereo_projection.hpp"

namespace glmbslam::frontend {

struct TrackedPoint {
  Eigen::Vector3d point_ref = Eigen::Vector3d::Zero();  ///< 3D point in the reference frame (triangulated)
  Eigen::Vector3d z_ref = Eigen::Vector3d::Zero();      ///< stereo measurement in the reference frame
  double sigma_ref = 1.0;
  Eigen::Vector3d z_cur = Eigen::Vector3d::Zero();  ///< measurement in the current frame (u_R unused if mono)
  double sigma_cur = 1.0;
  bool cur_stereo = true;  ///< false: only (u_L, v) of z_cur is observed
};

enum class PoseRefinerKind {
  kCeres,       ///< ceres::Problem on the SE(3) manifold with ceres::HuberLoss
  kGaussNewton  ///< hand-written Gauss–Newton (IRLS Huber weights)
};

/// "ceres" or "gauss_newton" (the values of the `vo.refiner` config key); throws std::invalid_argument else.
PoseRefinerKind pose_refiner_kind(const std::string& name);

struct PoseRefinementOptions {
  PoseRefinerKind refiner = PoseRefinerKind::kGaussNewton;  ///< the default of VoConfig::refiner
  double huber_delta = 2.0;                                 ///< Huber threshold on the whitened residual norm
  double chi2_threshold = 7.815;  ///< 3-dof gate; the 2-dof gate is scaled by 5.991 / 7.815
  int rounds = 2;                 ///< solve / reject rounds (another round only if the gate removed points)
  int max_iterations = 10;        ///< solver iterations per round
  /// Apply the gate at the initial pose too, before the first round (the start is already a refined pose,
  /// and points that fail there must not pull the first round's Huber solve).
  bool gate_at_start = false;
};

/// The refinement options of a VO configuration (refiner, huber_delta, chi2_threshold, rounds, iterations).
PoseRefinementOptions pose_refinement_options(const VoConfig& config);

struct PoseRefinementResult {
  Pose3 T_ref_cur = Pose3::Identity();
  Matrix6d covariance = Matrix6d::Identity();
  std::vector<char> inlier;  ///< per tracked point (1 = kept in the last round)
  /// per tracked point: eᵀ S⁻¹ e at the solution (whitening refreshed there), inliers and rejected points
  /// alike; NaN for a point behind the current camera. Empty if the refinement did not reach a solution.
  std::vector<double> chi2;
  int inliers = 0;
  bool success = false;  ///< false if too few points or a degenerate information matrix
};

PoseRefinementResult refine_stereo_pose(const StereoCamera& camera, const std::vector<TrackedPoint>& points,
                                        const Pose3& initial_T_ref_cur, const PoseRefinementOptions& options);

}  // namespace glmbslam::frontend
