#pragma once
// Settings of the stereo SLAM pipeline (`glmbslam run` on KITTI): one YAML file with the mappings
//   frontend:    ORB, stereo matching, visual odometry (frontend/frontend_config.hpp)
//   motion:      SE(3) motion driven by the VO (backend/models/se3_motion.hpp)
//   measurement: stereo measurement model (backend/models/stereo_measurement_model.hpp)
//   association: optional descriptor term of the landmark likelihood (same model; StereoMeasurementConfig)
//   rbpf:        particle filter and δ-GLMB map update (backend/rbpf/rbpf_config.hpp; child `glmb`)
//   lmb:         LMB-SLAM's labelled multi-Bernoulli map (algorithm lmb, lmb1; backend/lmb/lmb_config.hpp)
//   pipeline:    what this file declares below.
//   refine:      RFS maximum-likelihood refinement of the filter (--refine ml; app/refine_config.hpp)
// Every key has a default in code; config/kitti*.yaml document them. Unknown keys are errors.
#include <string>

#include <yaml-cpp/yaml.h>

#include "app/refine_config.hpp"
#include "backend/lmb/lmb_config.hpp"
#include "backend/models/se3_motion.hpp"
#include "backend/models/stereo_measurement_model.hpp"
#include "backend/rbpf/rbpf_config.hpp"
#include "frontend/frontend_config.hpp"
#include "frontend/pixel_noise_estimator.hpp"

namespace glmbslam::app {

struct PipelineSettings {
  int max_measurements = 150;  ///< stereo measurements handed to the backend per frame (spread over a grid)
  int grid_columns = 10;       ///< selection grid over the image: columns …
  int grid_rows = 4;           ///< … and rows; each cell contributes its strongest measurements in turn
  /// highest ORB pyramid level handed to the backend (its model has the level-0 pixel σ; see
  /// app/measurement_selection.hpp)
  int max_octave = 0;
  bool prefer_tracked =
      true;  ///< in each cell, first the features the VO tracked from last frame's selection
  /// The VO points the backend's control u_k, Q_k leaves out: "selected" (handed to it now: no pixel counted
  /// twice), "tracked" (handed to it now and in the previous frame: no pixel pair lost either) or "none"; see
  /// control_exclusion() in app/measurement_selection.hpp. The legacy key control_excludes_selected: true /
  /// false reads as "selected" / "none".
  std::string control_excludes = "selected";
  /// run the frontend of frames k+1 … k+3 (FrameSource::kLookahead) while the backend processes frame k
  bool overlap_frontend = true;
  bool write_plots = true;  ///< PNG plots next to metrics.json
  /// glmb2 / glmb1: δ-GLMB-SLAM with the optimal / prior proposal; lmb / lmb1: LMB-SLAM with the optimal /
  /// prior proposal; vo: no backend
  std::string algorithm = "glmb2";
  /// trajectory.txt holds the best particle's "proposal_mean" (Rao–Blackwellised estimate) or "sample" poses.
  std::string trajectory_estimate = "proposal_mean";
};

/// `measurement.pixel_sigma: auto` (the default): the backend's keypoint noise σ follows the sequence's,
/// estimated online from the visual odometry's residuals (frontend/pixel_noise_estimator.hpp) and clamped to
/// [pixel_sigma_floor, pixel_sigma_ceiling]. A number fixes σ. The VO weighs its residuals with
/// frontend.stereo.pixel_sigma either way.
struct PixelSigmaSettings {
  bool automatic = true;
  double floor = 0.3;    ///< measurement.pixel_sigma_floor (px)
  double ceiling = 2.0;  ///< measurement.pixel_sigma_ceiling (px)
};

struct StereoConfig {
  frontend::FrontendConfig frontend;
  backend::Se3MotionConfig motion;
  backend::StereoMeasurementConfig measurement;  ///< pixel_sigma: the fixed σ, or the start of `auto`
  PixelSigmaSettings pixel_sigma;
  backend::RbpfConfig rbpf;
  backend::LmbConfig lmb;
  PipelineSettings pipeline;
  RefineSettings refine;
};

/// The noise estimator's settings of `config` (the fixed σ as its initial value, floor, ceiling).
frontend::PixelNoiseOptions pixel_noise_options(const StereoConfig& config);

/// Defaults for the stereo pipeline (KITTI, paper 000's 20 m range, 10 particles).
StereoConfig default_stereo_config();

/// Camera-aware defaults: every key below that `root` does not set follows from the rectified calibration
/// (f·b, image size), scaled so that the KITTI 00-02 rig (f·b = 386 px·m, 1241×376) keeps its measured
/// values: the depth range (frontend.stereo.min_depth_m and measurement.min_depth: largest disparity 30 % of
/// the width capped at 1 m; measurement.max_depth: smallest disparity 4.8 px capped at 80 m; the frontend's
/// frontend.stereo.max_depth_m stays 80 m, for the VO's rotation), the clutter rate
/// (measurement.clutter_rate: 10 per 1241×376 image, by area), ORB features (frontend.orb.features: 2000 per
/// 1241×376, by area) and the selection grid (pipeline.grid_columns / grid_rows: cells of about 124×94 px).
void apply_camera_defaults(const YAML::Node& root, const StereoCalibration& calibration,
                           StereoConfig& config);

/// Reads a parsed YAML document (from `origin`, named in messages) over the defaults.
/// Throws ConfigError naming the key and origin on an unknown key, a wrong type or a value out of range.
StereoConfig parse_stereo_config(const YAML::Node& root, const std::string& origin);

}  // namespace glmbslam::app
