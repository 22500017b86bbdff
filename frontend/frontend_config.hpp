#pragma once
// Settings of the stereo frontend and the visual odometry, with their defaults (KITTI, 1241×376).
// YAML layout (see config/frontend_defaults.yaml): a `frontend` mapping holding `orb`, `stereo` and `vo`.
#include <string>

#include "core/config_node.hpp"

namespace glmbslam::frontend {

/// ORB extraction: FAST corners on every pyramid level, spread over the image by a grid, steered BRIEF.
struct OrbConfig {
  int features = 2000;         ///< target number of keypoints per image (all levels)
  int levels = 8;              ///< pyramid levels
  double scale_factor = 1.2;   ///< scale between consecutive levels
  int fast_threshold = 20;     ///< FAST threshold of the one pass over each level
  int min_fast_threshold = 7;  ///< FAST threshold re-run in the cells where the first found nothing
  int cell_size = 35;          ///< grid cell size in pixels of each level
  int edge_threshold = 19;     ///< keypoints closer than this to the border of their level are not detected
  bool parallel = true;        ///< extract the left and right image concurrently (a persistent worker thread)
};

/// Stereo matching along rectified rows.
struct StereoMatchConfig {
  double min_depth_m = 1.0;         ///< nearest accepted depth (sets the largest disparity)
  double max_depth_m = 80.0;        ///< farthest accepted depth (sets the smallest disparity)
  double row_band_px = 2.0;         ///< row tolerance at level 0; multiplied by scale_factor^octave
  int max_octave_difference = 1;    ///< left/right keypoints must be on levels at most this far apart
  int max_hamming = 75;             ///< best descriptor distance must be below this (of 256 bits)
  double ratio = 0.9;               ///< best < ratio · second best (candidates ≥ 2 px apart); 1 disables
  int sad_half_window = 5;          ///< SAD patch is (2w+1)² on the keypoint's level
  int sad_search_radius = 5;        ///< pixels searched left/right of the matched u_R on that level
  double outlier_sad_factor = 2.1;  ///< reject matches whose SAD exceeds this × the frame's median SAD
  /// Sub-pixel u_R cost: "centre" (ORB-SLAM2's: each patch relative to its centre pixel, parabola fit) or
  /// "zero_mean" (each patch relative to its mean, equiangular fit, kept where the centre cost's minimum is
  /// within one pixel of the level): unbiased and 4× sharper on rendered frames
  /// (tests/frontend/test_stereo_disparity_bias.cpp), but the filter is tuned for "centre"
  /// (docs/investigations.md).
  std::string subpixel_cost = "centre";
  /// Sub-pixel u_R: `fit` (the three-point fit of subpixel_cost) or `lk` (then a Lucas–Kanade refinement
  /// with a brightness offset on the interpolated row, free of the fit's pixel locking; stereo_matcher.cpp).
  /// On renders `lk` follows a point's disparity from frame to frame more faithfully; the filter is tuned for
  /// "fit" (docs/investigations.md).
  std::string subpixel_refine = "fit";
  /// Level the right camera's contrast to the left's before the sub-pixel search (σ_L / σ_R per frame from
  /// the descriptor matches' patches; stereo_gain.hpp): the costs remove a brightness offset, not a gain.
  bool gain_compensation = true;
  double pixel_sigma = 1.0;  ///< σ (pixels) of u_L, v, u_R at level 0; × scale_factor^octave above
};

/// Frame-to-frame stereo visual odometry.
struct VoConfig {
  double search_radius_px = 15.0;  ///< guided matching window at level 0 around the predicted projection
  double wide_search_radius_px =
      150.0;                    ///< window when the prediction is unreliable (start, after a failure)
  int max_hamming = 80;         ///< descriptor distance threshold for temporal matches
  double ratio = 0.9;           ///< best < ratio · second best for temporal matches; 1 disables
  int min_matches = 20;         ///< fewer guided matches → retry with the wide window, then fall back
  int min_inliers = 12;         ///< fewer PnP/refinement inliers → constant-velocity fallback
  int ransac_iterations = 100;  ///< EPnP RANSAC iterations
  double ransac_reprojection_px = 2.0;   ///< RANSAC inlier threshold (pixels, left image)
  double ransac_confidence = 0.99;       ///< RANSAC confidence
  std::string refiner = "gauss_newton";  ///< pose refinement solver: gauss_newton | ceres (same objective)
  double huber_delta = 2.0;              ///< Huber loss threshold on whitened residual norm (σ units)
  double chi2_threshold = 7.815;         ///< 3-dof χ² gate (95 %) for outlier rejection between rounds
  int refine_rounds = 2;                 ///< motion-only refinement solve / reject rounds
  int max_iterations = 10;               ///< solver iterations per round
  bool rematch_after_pnp = true;         ///< redo guided matching with the PnP pose before refinement
  /// With rematch_after_pnp: refine the RANSAC consensus first, rematch at its pose and drop the rematched
  /// pairs that fail the χ² gate there before the refinement (a moving car's points); false: rematch at the
  /// RANSAC pose and refine all rematched pairs.
  bool consensus_first = false;
  /// A byte-identical repeat of the previous stereo pair (a duplicated frame in a log) gets zero motion with
  /// these standard deviations; a still scene is tracked like any other frame.
  double repeat_sigma_translation_m = 0.001;
  double repeat_sigma_rotation_rad = 0.0002;
  double fallback_covariance_scale = 25.0;    ///< fallback Q = scale · last good Q + floor²
  double fallback_sigma_translation_m = 0.5;  ///< floor of the fallback standard deviation, translation
  double fallback_sigma_rotation_rad = 0.02;  ///< floor of the fallback standard deviation, rotation
};

struct FrontendConfig {
  OrbConfig orb;
  StereoMatchConfig stereo;
  VoConfig vo;
};

/// Reads the `frontend` mapping (children `orb`, `stereo`, `vo`; absent keys keep their defaults).
/// Validates ranges and calls finish() on each mapping, so unknown keys are ConfigErrors.
FrontendConfig load_frontend_config(ConfigNode& node);

}  // namespace glmbslam::frontend
