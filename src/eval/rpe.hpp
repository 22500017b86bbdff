#pragma once
// Relative pose error (Sturm et al., IROS 2012): for pose pairs (i, j),
// E = (T_gt,i⁻¹ T_gt,j)⁻¹ (T_est,i⁻¹ T_est,j); translation error ‖t(E)‖, rotation error angle(R(E)).
// Pairs are taken at a fixed frame delta (j = i + Δ) or at a distance delta along the ground-truth path
// (j = first frame whose path distance from i exceeds Δ metres, as the KITTI segments, every frame i).
#include "core/types.hpp"

namespace glmbslam::eval {

/// RPE statistics over all pairs at one delta.
struct RpeResult {
  bool by_distance = false;  ///< false: delta is in frames; true: delta is in metres along the ground truth
  double delta = 1.0;
  int pairs = 0;
  double trans_rmse_m = 0.0;  ///< NaN when pairs == 0 (all four statistics)
  double trans_mean_m = 0.0;
  double rot_rmse_deg = 0.0;
  double rot_mean_deg = 0.0;
};

/// RPE with j = i + delta_frames (delta_frames ≥ 1). Sizes must match (std::invalid_argument otherwise).
RpeResult evaluate_rpe_frames(const PoseList& gt, const PoseList& est, int delta_frames);

/// RPE with j = first frame whose ground-truth path distance from i exceeds delta_m (> 0).
RpeResult evaluate_rpe_distance(const PoseList& gt, const PoseList& est, double delta_m);

}  // namespace glmbslam::eval
