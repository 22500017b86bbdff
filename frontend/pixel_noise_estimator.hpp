#pragma once
// Online estimate of the keypoint noise σ (pixels, level 0) of a sequence from the visual odometry's
// residuals. The VO's motion-only refinement (stereo_pose_refiner.hpp) predicts each tracked point's residual
// e_i = π(T⁻¹ X_i) − z_cur,i with covariance σ² S̃_i, where S̃_i is the covariance at σ = 1 px (the
// current keypoint's noise plus the reference triangulation's, both of the same σ at level 0). So
// s_i = e_iᵀ S̃_i⁻¹ e_i ~ σ² χ²₃ at the true pose. The pose is fitted to the same residuals and absorbs 6 of
// their D dimensions (3 per stereo point, 2 per point seen in the left image only): E[Σ s_i] = σ² (D − 6), so
// each frame's s_i are scaled by D / (D − 6). Every residual of the refinement's input is used, not only its
// inliers, whose χ² gate would truncate the distribution at a σ-dependent point.
//
// Which scale: real keypoint residuals are not Gaussian but a narrow core with wide shoulders (corners that
// shift with the viewpoint, blur, rectification). On KITTI raw 0001 the core (median) gives 0.35 px and the
// 95 % point 0.92 px; on a rendered KITTI drive 0.29 and 0.49 px. The backend's Gaussian at the core's σ
// rejects the shoulders as clutter (KITTI raw 0001 ATE 0.17 m at 0.3 px vs 0.058 m at 1 px), so σ is the
// scale whose Gaussian holds a fraction `coverage` (95 %) of the residuals, σ² = q_0.95(s) / q_0.95(χ²₃),
// which for Gaussian residuals is their σ. Gross outliers (wrong matches, beyond 400 times the median's
// scale, i.e. 20 σ) are removed first; wrong matches nearer than that count as residuals, so the estimate
// assumes they are a few per cent at most (the VO's descriptor and ratio tests).
//
// Frames whose tracked features moved less than min_flow_px (a still camera) are not used: a corner seen at
// the same pixels is detected with the same error, which the residual between the two frames does not show.
// The estimate pools the samples of the last window_frames usable frames and is clamped to
// [floor, ceiling]; until min_samples are pooled it is the initial value.
#include <cmath>
#include <cstddef>
#include <deque>
#include <vector>

namespace glmbslam::frontend {

struct PixelNoiseOptions {
  double initial = 1.0;      ///< σ (px) reported until enough samples are pooled
  double floor = 0.3;        ///< lowest σ reported (px)
  double ceiling = 2.0;      ///< highest σ reported (px)
  int window_frames = 100;   ///< usable frames pooled (the most recent)
  int min_samples = 500;     ///< samples needed before the estimate replaces `initial`
  double min_flow_px = 2.0;  ///< a frame whose median feature motion is below this is not used
  double coverage = 0.97;    ///< σ's Gaussian holds this fraction of the residuals (file comment)
};

/// The p-quantile of χ²₃.
double chi2_3_quantile(double p);

/// σ² such that a fraction `coverage` of the samples s_i lies inside σ² times the `coverage` point of χ²₃
/// (for s_i ~ σ² χ²₃ that is σ²), after removing gross outliers beyond 400 times the median scale (see the
/// file comment). NaN for an empty input.
double coverage_chi2_3_scale(std::vector<double> s, double coverage);

class PixelNoiseEstimator {
 public:
  explicit PixelNoiseEstimator(const PixelNoiseOptions& options = {});

  /// One frame: `unit_chi2` holds s_i = e_iᵀ S̃_i⁻¹ e_i of stereo points (3 residual dimensions each, the
  /// covariance at σ = 1 px) at the pose fitted to the frame's `fit_dimensions` residual dimensions (all its
  /// points, of which these are a part); `median_flow_px` is the median image motion of its tracked features.
  /// Returns true if the frame was used.
  bool add_frame(const std::vector<double>& unit_chi2, int fit_dimensions, double median_flow_px);

  /// The clamped estimate (px), or the initial value before enough samples are pooled.
  double sigma() const { return sigma_; }
  /// The unclamped estimate (NaN before enough samples are pooled).
  double raw_sigma() const { return raw_sigma_; }
  /// True once enough samples were pooled: sigma() is an estimate, not the initial value.
  bool estimated() const { return !std::isnan(raw_sigma_); }
  std::size_t samples() const { return pooled_; }
  const PixelNoiseOptions& options() const { return options_; }

 private:
  PixelNoiseOptions options_;
  std::deque<std::vector<double>> frames_;  ///< corrected samples of the pooled frames
  std::size_t pooled_ = 0;
  double sigma_;
  double raw_sigma_;
};

}  // namespace glmbslam::frontend
