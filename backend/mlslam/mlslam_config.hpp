#pragma once
// Settings of RFS maximum-likelihood SLAM (paper 004, solved as EM / iteratively reweighted least squares;
// backend/mlslam/README.md). Every member is documented where it is declared; load_mlslam_config reads the
// YAML mapping "mlslam" (unknown keys are errors).
#include <string>

#include "core/config_node.hpp"

namespace glmbslam::backend {

struct MlSlamConfig {
  /// "rfs": associations summed out (Eq. 7); "nearest_neighbour": the vector ML baseline (Eq. 4) with hard
  /// nearest-neighbour associations re-made every round and a landmark for every unassociated measurement.
  std::string association = "rfs";
  int max_rounds = 30;      ///< EM rounds (E-step + M-step), cardinality moves included
  double tolerance = 1e-4;  ///< stop when the log-likelihood rises by less than this (nats)
  /// Also stop when a round raises l by less than this fraction of its rise since the start (0 = off): on a
  /// long stereo run the last rounds add a few nats out of thousands and cost as much as the first.
  double relative_tolerance = 0.0;
  int solver_iterations = 10;  ///< Levenberg–Marquardt iterations per M-step
  /// Levenberg–Marquardt's initial trust region radius of every M-step (Ceres' default 10⁴; its damping is
  /// 1/radius × diag(JᵀJ)). Each EM round restarts it. The long-wavelength modes of a long trajectory
  /// (slow bends, a drift that builds up over thousands of poses) have eigenvalues of JᵀJ many orders below
  /// its diagonal, so a short M-step from 10⁴ barely moves them; from 10⁸ the first step is Gauss–Newton's.
  double initial_trust_region_radius = 1e4;
  /// The motion noise of the motion factors: "configured" (the motion model's Q) or "estimated" (s·Q with the
  /// scale s of maximum likelihood, re-estimated in every M-step after the trajectory: s = Σ rᵀQ⁻¹r / (d·K),
  /// r the motion residuals, d their dimension). A filter's motion noise is often set wide on purpose (its
  /// particles must cover slips and outliers), which the batch solve does not need. RfsMlSlam only.
  std::string motion_noise = "configured";
  /// The M-step's linear solver (Ceres; m_step_linear_solver.hpp): "dense_schur" / "sparse_schur" (landmarks
  /// eliminated, the reduced pose system factorised densely by Eigen / sparsely by CHOLMOD),
  /// "sparse_normal_cholesky" (the whole normal equations, fill-reducing ordering), "iterative_schur"
  /// (conjugate gradients on the reduced system, Schur–Jacobi preconditioned), or "auto": dense_schur up to
  /// kAutoDensePoses poses, sparse_schur up to kAutoSchurPoses, sparse_normal_cholesky beyond. On rendered
  /// KITTI 07 with 3 LM iterations sparse_schur took 0.6 s per M-step on 300 frames but 18.5 s on all 1101
  /// (landmarks seen from many poses fill the reduced pose system in), iterative_schur 18 s on 700 frames. A
  /// sliding window's reduced system (60 × 60 for 10 stereo poses) is cheaper dense: no symbolic analysis and
  /// no BLAS threads, which spin (sched_yield) against the frontend's thread (docs/investigations.md).
  std::string linear_solver = "auto";
  static constexpr std::size_t kAutoDensePoses = 50;
  static constexpr std::size_t kAutoSchurPoses = 200;
  int max_assignments = 50;          ///< Murty: ranked assignments per independent block of a scan
  double assignment_log_gap = 9.2;   ///< Murty: stop below e^{-gap} of the best assignment's weight
  double gate = 16.0;                ///< squared Mahalanobis gate of a landmark-measurement pair
  double min_responsibility = 1e-4;  ///< β below this contributes no M-step residual
  /// Smooth field-of-view border (digest 3.5): p_D falls as a logistic of the distance to the border with
  /// these widths; ≤ 0 = the sensor's noise std (σ_r, σ_b).
  double border_range_m = 0.0;
  double border_bearing_rad = 0.0;
  /// Stereo: width (px) of the logistic at the image borders; ≤ 0 = the pixel σ. (border_range_m is the
  /// width in depth there; ≤ 0 = 2 % of the maximum depth.)
  double border_pixels = 0.0;
  bool cardinality_moves = true;      ///< births, deaths and merges between EM rounds (kept if l rises)
  double birth_responsibility = 0.5;  ///< a measurement is unexplained when its clutter responsibility ≥ this
  /// Unexplained measurements closer than this form one birth candidate; ≤ 0 = 10 σ_r.
  double birth_radius_m = 0.0;
  int birth_min_support = 2;      ///< a birth candidate needs this many unexplained measurements
  double death_ratio = 0.5;       ///< try removing a landmark detected < ratio × its expected detections
  double merge_distance_m = 0.0;  ///< try merging landmarks closer than this; ≤ 0 = 10 σ_r
  /// Standalone: solve on steps 0..k every this many steps, each new stretch dead-reckoned from the last
  /// refined pose (0 = one batch from the odometry, which can stay stuck where the drift exceeds the gate).
  int incremental_steps = 5;
  /// Standalone with incremental_steps > 0: solve only the last this many steps at each increment (their
  /// first pose held, the landmarks they may see; older poses and landmarks kept), then one solve of the
  /// whole problem at the end. 0 = every increment solves all the steps so far (cost quadratic in their
  /// number: hours on Victoria Park's 7230 scans).
  int incremental_window = 0;
  /// Standalone: each new pose starts at the best of n points per dimension of its motion noise's ±3σ box
  /// (x = f(x_{i−1}, u) ⊕ L t, L Lᵀ = P̄, t on the grid), scored by log g + log p(Z_i | x, M) with the map so
  /// far (0 = dead reckoning). For odometry much noisier than the sensor, where a dead-reckoned pose puts
  /// the known landmarks outside the gate and EM never sees them (paper 004's 1D problem: 10 cm odometry
  /// against 1 cm measurements). n^d evaluations per pose, d the pose dimension.
  int initial_pose_search = 0;
};

void load_mlslam_config(ConfigNode node, MlSlamConfig& config);

/// Throws ConfigError if a value is inconsistent.
void validate_mlslam_config(const MlSlamConfig& config);

}  // namespace glmbslam::backend
