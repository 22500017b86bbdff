#include "app/stereo_config.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>

#include "backend/rbpf/rbpf_config.hpp"
#include "core/config_node.hpp"

namespace glmbslam::app {
namespace {

void load_motion(ConfigNode node, backend::Se3MotionConfig& c) {
  node.read_in_range("covariance_inflation", c.covariance_inflation, 1e-6, 1e6);
  node.read_in_range("min_sigma_translation", c.min_sigma_translation, 0.0, 10.0);
  node.read_in_range("min_sigma_rotation", c.min_sigma_rotation, 0.0, 1.0);
  node.finish();
}

/// measurement.pixel_sigma: `auto` or a number in [1e-3, 100] px.
void load_pixel_sigma(ConfigNode& node, backend::StereoMeasurementConfig& c, PixelSigmaSettings& a) {
  std::string text;
  node.read("pixel_sigma", text);
  if (!text.empty()) {
    if (text == "auto") {
      a.automatic = true;
    } else {
      std::size_t used = 0;
      double value = std::nan("");
      try {
        value = std::stod(text, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != text.size() || !(value >= 1e-3 && value <= 100.0))
        node.fail("pixel_sigma", "must be auto or a number in [0.001, 100] (pixels), not '" + text + "'");
      c.pixel_sigma = value;
      a.automatic = false;
    }
  }
  node.read_in_range("pixel_sigma_floor", a.floor, 1e-3, 100.0);
  node.read_in_range("pixel_sigma_ceiling", a.ceiling, 1e-3, 100.0);
  if (a.ceiling < a.floor) node.fail("pixel_sigma_ceiling", "must not be below pixel_sigma_floor");
}

void load_measurement(ConfigNode node, backend::StereoMeasurementConfig& c, PixelSigmaSettings& a) {
  load_pixel_sigma(node, c, a);
  node.read_in_range("min_depth", c.min_depth, 0.01, 1000.0);
  node.read_in_range("max_depth", c.max_depth, 0.02, 10000.0);
  if (c.max_depth <= c.min_depth) node.fail("max_depth", "must be greater than min_depth");
  node.read_in_range("border", c.border, 0.0, 1000.0);
  node.read_in_range("p_detect_inside", c.p_detect_inside, 0.0, 1.0);
  node.read_in_range("p_survive_inside", c.p_survive_inside, 0.0, 1.0);
  node.read_in_range("p_survive_outside", c.p_survive_outside, 0.0, 1.0);
  node.read_in_range("clutter_rate", c.clutter_rate, 0.0, 1e6);
  node.finish();
}

void load_association(ConfigNode node, backend::StereoMeasurementConfig& c) {
  node.read("use_descriptors", c.use_descriptors);
  node.read_in_range("descriptor_threshold", c.descriptor_threshold, 0.0, 256.0);
  node.read_in_range("descriptor_scale", c.descriptor_scale, 0.0, 100.0);
  node.read_in_range("descriptor_max_log_ratio", c.descriptor_max_log_ratio, 0.0, 1000.0);
  node.finish();
}

void load_pipeline(ConfigNode node, PipelineSettings& c) {
  node.read_in_range("max_measurements", c.max_measurements, 1, 100000);
  node.read_in_range("grid_columns", c.grid_columns, 1, 1000);
  node.read_in_range("grid_rows", c.grid_rows, 1, 1000);
  node.read_in_range("max_octave", c.max_octave, 0, 31);
  node.read("prefer_tracked", c.prefer_tracked);
  node.read_choice("control_excludes", c.control_excludes, {"tracked", "selected", "none"});
  if (node.has("control_excludes_selected")) {  // the key before control_excludes
    if (node.has("control_excludes"))
      node.fail("control_excludes_selected",
                "give control_excludes only (control_excludes_selected is its old form)");
    bool legacy = true;
    node.read("control_excludes_selected", legacy);
    c.control_excludes = legacy ? "selected" : "none";
  }
  node.read("overlap_frontend", c.overlap_frontend);
  node.read("write_plots", c.write_plots);
  node.read_choice("algorithm", c.algorithm, {"glmb2", "glmb1", "lmb", "lmb1", "vo"});
  node.read_choice("trajectory_estimate", c.trajectory_estimate, {"proposal_mean", "sample"});
  node.finish();
}

}  // namespace

frontend::PixelNoiseOptions pixel_noise_options(const StereoConfig& config) {
  frontend::PixelNoiseOptions o;
  o.initial = config.measurement.pixel_sigma;
  o.floor = config.pixel_sigma.floor;
  o.ceiling = config.pixel_sigma.ceiling;
  return o;
}

StereoConfig default_stereo_config() {
  StereoConfig c;
  // One particle whose pose is the optimal-kernel proposal's mean (no sampling noise): with the VO control
  // (rotation error ~0.002 deg per frame on rendered 00) the draws of 10 particles (paper 000's, as wide as
  // the proposal) add more error than their diversity removes. Rendered 00 (4541 frames), SLAM t_rel / r_rel:
  // N = 1 mean 0.281 % / 0.154, N = 10 0.403 % / 0.190, VO 0.323 % / 0.196 (figures in config/kitti00-02.yaml
  // and the README).
  c.rbpf.particles = 1;
  c.rbpf.single_particle = "mean";
  // With --particles N > 1: each particle takes its proposal's mean (a draw as wide as the posterior put its
  // error into every later pose), and the children of one parent share their sampled normaliser (its sampler
  // noise otherwise picks the winners: rendered 00 seeds 0-4, N = 10 ATE 2.40 -> 1.98 m, N = 1 2.16 m;
  // docs/investigations.md, "Particles over five seeds on rendered 00").
  c.rbpf.proposal_scale = 0.0;
  c.rbpf.particle_normalizer = "sibling_mean";
  c.rbpf.glmb.gibbs_samples = 60;
  c.rbpf.glmb.max_hypotheses = 30;
  c.rbpf.proposal_gibbs_samples = 20;
  c.rbpf.proposal_hypotheses = 2;
  c.rbpf.glmb.gate_threshold = 16.27;  // χ²₃ at 1 − 1e-3
  // far landmarks leave the update (exact; KITTI moves ≤ ~3 m per frame): cost follows the landmarks in view
  c.rbpf.glmb.freeze_margin = 5.0;
  // The keypoint noise of level-0 keypoints (pipeline.max_octave 0 hands only those to the backend):
  // estimated per sequence (c.pixel_sigma.automatic), starting from 1 px. Rendered stop-and-go (poses/00
  // frames 0-399 with 100 still frames) SLAM t_rel 0.189 -> 0.163 % (VO 0.162), clean 400 frames 0.161 ->
  // 0.123 % (VO 0.139), rendered 00 0.281 -> 0.246 %; KITTI raw 0001 seeds 0-4 ATE 0.0575 +- 0.0026 -> 0.0596
  // +- 0.0031 m.
  c.measurement.pixel_sigma = 1.0;
  // Far points fix the rotation: 80 m (the frontend's stereo range) instead of paper 000's 20 m. KITTI raw
  // 0001, N = 1 mean, seed 0, ATE / drift: 20 m 0.062 m / 0.63 %, 40 m 0.061 / 0.55, 80 m 0.059 / 0.51.
  c.measurement.max_depth = 80.0;
  // ORB descriptors in the association: rendered 00 t_rel 0.335 -> 0.281 %, r_rel 0.171 -> 0.154, and faster
  // (fewer association hypotheses); KITTI raw 0001 seeds 0-4 ATE 0.0579 -> 0.0589 m (the OXTS ground truth's
  // per-frame jitter, ~5 cm, dominates there), drift 0.530 -> 0.513 %.
  c.measurement.use_descriptors = true;
  return c;
}

void apply_camera_defaults(const YAML::Node& root, const StereoCalibration& calibration, StereoConfig& c) {
  if (!(calibration.fx > 0.0) || !(calibration.baseline > 0.0) || calibration.width <= 0 ||
      calibration.height <= 0)
    return;
  auto absent = [&](const char* section, const char* sub, const char* key) {
    if (!root || !root.IsMap() || !root[section]) return true;
    const YAML::Node s = sub ? root[section][sub] : root[section];
    return !s || !s.IsMap() || !s[key];
  };
  const double fb = calibration.fx * calibration.baseline;  // disparity (px) × depth (m)
  const double width = calibration.width, height = calibration.height;
  const double area = width * height / (1241.0 * 376.0);
  const double min_depth = std::min(1.0, fb / (0.3 * width));
  const double max_depth = std::min(80.0, fb / 4.8);
  if (absent("frontend", "stereo", "min_depth_m")) c.frontend.stereo.min_depth_m = min_depth;
  // The VO keeps its points to 80 m whatever the rig: far points fix the rotation even at a fraction of a
  // pixel of disparity (the pose refinement weighs each by its triangulation covariance). Scaling this range
  // with f·b as below cost a 640×480 rig with f·b = 50 px (10.5 m) VO t_rel 2.61 % against 0.93 % at 80 m on
  // rendered 05 (docs/investigations.md, "Another rig: the VO's stereo range").
  if (absent("frontend", "stereo", "max_depth_m")) c.frontend.stereo.max_depth_m = 80.0;
  if (absent("measurement", nullptr, "min_depth")) c.measurement.min_depth = min_depth;
  if (absent("measurement", nullptr, "max_depth")) c.measurement.max_depth = max_depth;
  if (absent("measurement", nullptr, "clutter_rate")) c.measurement.clutter_rate = 10.0 * area;
  if (absent("frontend", "orb", "features"))
    c.frontend.orb.features = static_cast<int>(std::lround(2000.0 * std::min(1.0, area)));
  if (absent("pipeline", nullptr, "grid_columns"))
    c.pipeline.grid_columns = std::max(1, static_cast<int>(std::lround(width / 124.1)));
  if (absent("pipeline", nullptr, "grid_rows"))
    c.pipeline.grid_rows = std::max(1, static_cast<int>(std::lround(height / 94.0)));
}

StereoConfig parse_stereo_config(const YAML::Node& root, const std::string& origin) {
  StereoConfig c = default_stereo_config();
  ConfigNode node(root && root.IsMap() ? root : YAML::Node(YAML::NodeType::Map), origin, "");
  if (root && !root.IsNull() && !root.IsMap()) throw InputError(origin, "config must be a YAML mapping");
  if (node.has("frontend")) {
    ConfigNode f = node.child("frontend");
    c.frontend = frontend::load_frontend_config(f);
  }
  load_motion(node.child("motion"), c.motion);
  load_measurement(node.child("measurement"), c.measurement, c.pixel_sigma);
  load_association(node.child("association"), c.measurement);
  backend::load_rbpf_config(node.child("rbpf"), c.rbpf);
  if (node.has("lmb")) backend::load_lmb_config(node.child("lmb"), c.lmb);
  load_pipeline(node.child("pipeline"), c.pipeline);
  if (node.has("refine")) load_refine_config(node.child("refine"), c.refine);
  node.finish();
  return c;
}

}  // namespace glmbslam::app
