#pragma once
// The KITTI odometry metric exactly as the official devkit (evaluate_odometry.cpp) computes it:
// - distances along the ground-truth path accumulated in single precision (float, as the devkit does);
// - a segment starts every `step_size` frames (10); for each length L, its last frame is the first frame i
// with
//   dist[i] > dist[first] + L (strict, as the devkit); segments running past the end are skipped;
// - E = (ΔT_est)⁻¹·ΔT_gt with ΔT = T_first⁻¹·T_last (general 4×4 inverse, as the devkit's Matrix::inv);
// - t_err = ‖t(E)‖ / L, r_err = acos(clamp(0.5·(trace(R(E)) − 1), −1, 1)) / L (the acos in float, as the
// devkit);
// - the sequence figures are plain means over all segments of all lengths.
#include <vector>

#include "core/types.hpp"

namespace glmbslam::eval {

/// The devkit's segment lengths: 100, 200, ..., 800 m.
std::vector<double> kitti_standard_lengths();
/// Shorter lengths for short drives (reported as "kitti_short"): 10, 20, ..., 80 m.
std::vector<double> kitti_short_lengths();

/// Cumulative distance along the path (float accumulation, as the devkit's trajectoryDistances).
std::vector<float> trajectory_distances(const PoseList& poses);

/// One evaluated segment.
struct KittiSegmentError {
  int first_frame = 0;
  int last_frame = 0;
  double length_m = 0.0;
  double t_err = 0.0;  ///< translation error per metre (dimensionless)
  double r_err = 0.0;  ///< rotation error per metre (rad/m)
};

/// Means over the segments of one length.
struct KittiLengthResult {
  double length_m = 0.0;
  int segments = 0;
  double t_rel_percent = 0.0;       ///< NaN if segments == 0
  double r_rel_deg_per_100m = 0.0;  ///< NaN if segments == 0
};

/// The sequence result.
struct KittiResult {
  int segments = 0;
  double t_rel_percent = 0.0;       ///< mean t_err × 100; NaN if no segment fits in the path
  double r_rel_deg_per_100m = 0.0;  ///< mean r_err in deg/m × 100; NaN if no segment fits
  std::vector<KittiLengthResult> per_length;
  std::vector<KittiSegmentError> segment_errors;
};

/// Evaluates `est` against `gt` (same number of poses, else std::invalid_argument).
KittiResult evaluate_kitti(const PoseList& gt, const PoseList& est,
                           const std::vector<double>& lengths = kitti_standard_lengths(), int step_size = 10);

}  // namespace glmbslam::eval
