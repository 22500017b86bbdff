#pragma once
// Umeyama alignment of point sets and the absolute trajectory error (ATE) built on it.
// Umeyama, "Least-squares estimation of transformation parameters between two point patterns", PAMI 1991.
#include <vector>

#include <Eigen/Core>

#include "core/types.hpp"

namespace glmbslam::eval {

/// A similarity transform p ↦ scale·rotation·p + translation (scale = 1 for a rigid transform).
struct Similarity3 {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (rotation * p) + translation; }
};

/// Least-squares transform mapping `source` onto `target` (3×N each, N ≥ 1): minimises Σ‖target_i −
/// (s·R·source_i + t)‖² over R ∈ SO(3), t, and s > 0 if `with_scale` (else s = 1). Umeyama's eqs. (40)–(42),
/// with the reflection fix. Degenerate inputs (N < 3 or collinear points) return one of the minimisers.
/// Throws std::invalid_argument if the sizes differ or N = 0.
Similarity3 umeyama_alignment(const Eigen::Matrix3Xd& source, const Eigen::Matrix3Xd& target,
                              bool with_scale);

/// Positions (translations) of a trajectory as a 3×N matrix.
Eigen::Matrix3Xd positions_of(const PoseList& poses);

/// Absolute trajectory error of the positions, after aligning the estimate to the ground truth.
struct AteResult {
  int poses = 0;
  double se3_rmse_m = 0.0;   ///< RMSE after the best rigid (SE(3)) alignment
  double sim3_rmse_m = 0.0;  ///< RMSE after the best similarity (Sim(3)) alignment (NaN: ground truth still)
  double sim3_scale = 1.0;  ///< scale of that similarity (estimate → ground truth; NaN: ground truth still)
  Similarity3 se3_alignment;
  Similarity3 sim3_alignment;
  std::vector<double> se3_errors_m;   ///< per-pose position error after the SE(3) alignment
  std::vector<double> sim3_errors_m;  ///< per-pose position error after the Sim(3) alignment (empty: NaN)
};

/// Below this RMS spread of the ground-truth positions (m) the Sim(3) figures are undefined (NaN, no errors).
constexpr double kMinSim3Spread = 1e-6;

/// ATE of `est` against `gt` (same size ≥ 1, else std::invalid_argument). Sim(3) is NaN when the ground truth
/// does not move (kMinSim3Spread).
AteResult evaluate_ate(const PoseList& gt, const PoseList& est);

}  // namespace glmbslam::eval
