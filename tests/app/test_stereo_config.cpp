// The shipped stereo configs parse and document exactly the built-in defaults; bad keys are errors.
#include <filesystem>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "app/stereo_config.hpp"
#include "core/error.hpp"

namespace glmbslam::app {
namespace {

void expect_same(const StereoConfig& a, const StereoConfig& b, const std::string& file) {
  SCOPED_TRACE(file);
  EXPECT_EQ(a.frontend.orb.features, b.frontend.orb.features);
  EXPECT_EQ(a.rbpf.proposal_scale, b.rbpf.proposal_scale);
  EXPECT_EQ(a.rbpf.particle_normalizer, b.rbpf.particle_normalizer);
  EXPECT_EQ(a.frontend.stereo.max_depth_m, b.frontend.stereo.max_depth_m);
  EXPECT_EQ(a.frontend.vo.min_inliers, b.frontend.vo.min_inliers);
  EXPECT_EQ(a.motion.covariance_inflation, b.motion.covariance_inflation);
  EXPECT_EQ(a.motion.min_sigma_translation, b.motion.min_sigma_translation);
  EXPECT_EQ(a.motion.min_sigma_rotation, b.motion.min_sigma_rotation);
  EXPECT_EQ(a.measurement.pixel_sigma, b.measurement.pixel_sigma);
  EXPECT_EQ(a.pixel_sigma.automatic, b.pixel_sigma.automatic);
  EXPECT_EQ(a.pixel_sigma.floor, b.pixel_sigma.floor);
  EXPECT_EQ(a.pixel_sigma.ceiling, b.pixel_sigma.ceiling);
  EXPECT_EQ(a.measurement.min_depth, b.measurement.min_depth);
  EXPECT_EQ(a.measurement.max_depth, b.measurement.max_depth);
  EXPECT_EQ(a.measurement.border, b.measurement.border);
  EXPECT_EQ(a.measurement.p_detect_inside, b.measurement.p_detect_inside);
  EXPECT_EQ(a.measurement.p_survive_inside, b.measurement.p_survive_inside);
  EXPECT_EQ(a.measurement.p_survive_outside, b.measurement.p_survive_outside);
  EXPECT_EQ(a.measurement.clutter_rate, b.measurement.clutter_rate);
  EXPECT_EQ(a.rbpf.particles, b.rbpf.particles);
  EXPECT_EQ(a.rbpf.seed, b.rbpf.seed);
  EXPECT_EQ(a.rbpf.proposal, b.rbpf.proposal);
  EXPECT_EQ(a.rbpf.weighting, b.rbpf.weighting);
  EXPECT_EQ(a.rbpf.resampling, b.rbpf.resampling);
  EXPECT_EQ(a.rbpf.ess_threshold, b.rbpf.ess_threshold);
  EXPECT_EQ(a.rbpf.proposal_mixture, b.rbpf.proposal_mixture);
  EXPECT_EQ(a.rbpf.proposal_hypotheses, b.rbpf.proposal_hypotheses);
  EXPECT_EQ(a.rbpf.proposal_min_weight, b.rbpf.proposal_min_weight);
  EXPECT_EQ(a.rbpf.proposal_gibbs_samples, b.rbpf.proposal_gibbs_samples);
  EXPECT_EQ(a.rbpf.proposal_max_components, b.rbpf.proposal_max_components);
  EXPECT_EQ(a.rbpf.ipl_iterations, b.rbpf.ipl_iterations);
  EXPECT_EQ(a.rbpf.ipl_tolerance, b.rbpf.ipl_tolerance);
  EXPECT_EQ(a.rbpf.glmb.birth_prob_unexplained, b.rbpf.glmb.birth_prob_unexplained);
  EXPECT_EQ(a.rbpf.glmb.birth_prob_explained, b.rbpf.glmb.birth_prob_explained);
  EXPECT_EQ(a.rbpf.glmb.births, b.rbpf.glmb.births);
  EXPECT_EQ(a.rbpf.glmb.gate_threshold, b.rbpf.glmb.gate_threshold);
  EXPECT_EQ(a.rbpf.glmb.gibbs_samples, b.rbpf.glmb.gibbs_samples);
  EXPECT_EQ(a.rbpf.glmb.max_hypotheses, b.rbpf.glmb.max_hypotheses);
  EXPECT_EQ(a.rbpf.glmb.prune_threshold, b.rbpf.glmb.prune_threshold);
  EXPECT_EQ(a.pipeline.max_measurements, b.pipeline.max_measurements);
  EXPECT_EQ(a.pipeline.grid_columns, b.pipeline.grid_columns);
  EXPECT_EQ(a.pipeline.grid_rows, b.pipeline.grid_rows);
  EXPECT_EQ(a.pipeline.overlap_frontend, b.pipeline.overlap_frontend);
  EXPECT_EQ(a.pipeline.control_excludes, b.pipeline.control_excludes);
  EXPECT_EQ(a.pipeline.algorithm, b.pipeline.algorithm);
  EXPECT_EQ(a.pipeline.trajectory_estimate, b.pipeline.trajectory_estimate);
  EXPECT_EQ(a.refine.window, b.refine.window);
  EXPECT_EQ(a.refine.every, b.refine.every);
  EXPECT_EQ(a.refine.window_rounds, b.refine.window_rounds);
  EXPECT_EQ(a.refine.final_pass, b.refine.final_pass);
  EXPECT_EQ(a.refine.final_start, b.refine.final_start);
  EXPECT_EQ(a.refine.final_solver_iterations, b.refine.final_solver_iterations);
  EXPECT_EQ(a.refine.final_trust_region_radius, b.refine.final_trust_region_radius);
  EXPECT_EQ(a.refine.loop_closure, b.refine.loop_closure);
}

TEST(StereoConfig, ShippedFilesDocumentTheBuiltInDefaults) {
  const StereoConfig defaults = default_stereo_config();
  for (const char* name : {"kitti00-02.yaml", "kitti03.yaml", "kitti04-12.yaml", "kitti_raw.yaml"}) {
    const auto path = std::filesystem::path(GLMBSLAM_SOURCE_DIR) / "config" / name;
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    expect_same(parse_stereo_config(YAML::LoadFile(path.string()), path.string()), defaults, name);
  }
}

TEST(StereoConfig, TheFinalPassTakesItsOwnMStepSettingsAndTheWindowsKeepTheirs) {
  const StereoConfig c = parse_stereo_config(
      YAML::Load(
          "refine:\n  final_solver_iterations: 2\n  final_trust_region_radius: 1.0e+6\n"
          "  mlslam:\n    solver_iterations: 4\n    initial_trust_region_radius: 1.0e+3\n    gate: 9.0\n"),
      "test.yaml");
  EXPECT_EQ(c.refine.ml.solver_iterations, 4);
  EXPECT_EQ(c.refine.ml.initial_trust_region_radius, 1e3);
  const backend::MlSlamConfig final_pass = c.refine.final_pass_mlslam_config();
  EXPECT_EQ(final_pass.solver_iterations, 2);
  EXPECT_EQ(final_pass.initial_trust_region_radius, 1e6);
  EXPECT_EQ(final_pass.gate, 9.0);  // the rest is the windows'
}

TEST(StereoConfig, UnknownKeysWrongTypesAndBadRangesAreErrorsNamingTheKey) {
  auto expect_error = [](const std::string& yaml, const std::string& key) {
    try {
      parse_stereo_config(YAML::Load(yaml), "test.yaml");
      ADD_FAILURE() << "no error for " << yaml;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("test.yaml"), std::string::npos) << e.what();
    }
  };
  expect_error("rbpf:\n  partcles: 3\n", "partcles");
  expect_error("measurement:\n  max_depth: far\n", "max_depth");
  expect_error("measurement:\n  min_depth: 30\n  max_depth: 20\n", "max_depth");
  expect_error("pipeline:\n  algorithm: glmb3\n", "algorithm");
  expect_error("pipline:\n  algorithm: glmb1\n", "pipline");
  expect_error("refine:\n  final_trust_region_radius: -1\n", "final_trust_region_radius");
  expect_error("refine:\n  final_solver_iterations: 0\n", "final_solver_iterations");
  expect_error("refine:\n  mlslam:\n    initial_trust_region_radius: 0\n", "initial_trust_region_radius");
  expect_error("frontend:\n  orb:\n    featurs: 10\n", "featurs");
  expect_error("measurement:\n  pixel_sigma: automatic\n", "pixel_sigma");
  expect_error("measurement:\n  pixel_sigma: 0.5px\n", "pixel_sigma");
  expect_error("measurement:\n  pixel_sigma: 0\n", "pixel_sigma");
  expect_error("measurement:\n  pixel_sigma: [1]\n", "pixel_sigma");
  expect_error("measurement:\n  pixel_sigma_floor: -1\n", "pixel_sigma_floor");
  expect_error("measurement:\n  pixel_sigma_floor: 1.5\n  pixel_sigma_ceiling: 1\n", "pixel_sigma_ceiling");
  expect_error("pipeline:\n  control_excludes: all\n", "control_excludes");
  expect_error("pipeline:\n  control_excludes: none\n  control_excludes_selected: true\n",
               "control_excludes_selected");
}

// pipeline.control_excludes (selected, the default; tracked; none); the key before it,
// control_excludes_selected, still reads: true as selected, false as none.
TEST(StereoConfig, ControlExcludesAndItsLegacyKey) {
  EXPECT_EQ(default_stereo_config().pipeline.control_excludes, "selected");
  auto parse = [](const std::string& yaml) {
    return parse_stereo_config(YAML::Load(yaml), "test.yaml").pipeline.control_excludes;
  };
  EXPECT_EQ(parse("pipeline:\n  control_excludes: tracked\n"), "tracked");
  EXPECT_EQ(parse("pipeline:\n  control_excludes: none\n"), "none");
  EXPECT_EQ(parse("pipeline:\n  control_excludes_selected: true\n"), "selected");
  EXPECT_EQ(parse("pipeline:\n  control_excludes_selected: false\n"), "none");
}

// measurement.pixel_sigma: `auto` (the default: estimated per sequence, between the floor and the ceiling) or
// a fixed number of pixels.
TEST(StereoConfig, PixelSigmaIsAutoOrANumber) {
  const StereoConfig d = default_stereo_config();
  EXPECT_TRUE(d.pixel_sigma.automatic);
  EXPECT_EQ(d.measurement.pixel_sigma, 1.0);  // the estimate's starting value
  EXPECT_EQ(d.pixel_sigma.floor, 0.3);
  EXPECT_EQ(d.pixel_sigma.ceiling, 2.0);
  const StereoConfig a = parse_stereo_config(
      YAML::Load("measurement:\n  pixel_sigma: auto\n  pixel_sigma_floor: 0.5\n  pixel_sigma_ceiling: 1.5\n"),
      "test.yaml");
  EXPECT_TRUE(a.pixel_sigma.automatic);
  EXPECT_EQ(a.pixel_sigma.floor, 0.5);
  EXPECT_EQ(a.pixel_sigma.ceiling, 1.5);
  const frontend::PixelNoiseOptions o = pixel_noise_options(a);
  EXPECT_EQ(o.initial, 1.0);
  EXPECT_EQ(o.floor, 0.5);
  EXPECT_EQ(o.ceiling, 1.5);
  const StereoConfig f = parse_stereo_config(YAML::Load("measurement:\n  pixel_sigma: 0.7\n"), "test.yaml");
  EXPECT_FALSE(f.pixel_sigma.automatic);
  EXPECT_EQ(f.measurement.pixel_sigma, 0.7);
  const StereoConfig i = parse_stereo_config(YAML::Load("measurement:\n  pixel_sigma: 2\n"), "test.yaml");
  EXPECT_FALSE(i.pixel_sigma.automatic);
  EXPECT_EQ(i.measurement.pixel_sigma, 2.0);
}

TEST(StereoConfig, ValuesOverrideDefaults) {
  const StereoConfig c = parse_stereo_config(
      YAML::Load("rbpf:\n  particles: 4\n  glmb:\n    gibbs_samples: 7\npipeline:\n  algorithm: glmb1\n"),
      "test.yaml");
  EXPECT_EQ(c.rbpf.particles, 4);
  EXPECT_EQ(c.rbpf.glmb.gibbs_samples, 7);
  EXPECT_EQ(c.pipeline.algorithm, "glmb1");
}

TEST(StereoConfig, CameraDefaultsFollowTheRigAndKeepTheVosStereoRange) {
  // A 640×480 rig with f·b = 50.4 px: the backend's range shrinks to a 4.8 px disparity, the VO keeps 80 m
  // (far points fix its rotation: docs/investigations.md, "Another rig: the VO's stereo range").
  StereoCalibration rig;
  rig.fx = rig.fy = 420.0;
  rig.cx = 320.0;
  rig.cy = 240.0;
  rig.baseline = 0.12;
  rig.width = 640;
  rig.height = 480;
  StereoConfig c = default_stereo_config();
  apply_camera_defaults(YAML::Node(), rig, c);
  EXPECT_DOUBLE_EQ(c.frontend.stereo.max_depth_m, 80.0);
  const double fb = rig.fx * rig.baseline;
  EXPECT_DOUBLE_EQ(c.measurement.max_depth, fb / 4.8);
  EXPECT_DOUBLE_EQ(c.frontend.stereo.min_depth_m, fb / (0.3 * 640.0));
  EXPECT_DOUBLE_EQ(c.measurement.min_depth, fb / (0.3 * 640.0));
  EXPECT_EQ(c.frontend.orb.features, 1317);  // 2000 × 640·480 / (1241·376)
  EXPECT_EQ(c.pipeline.grid_columns, 5);
  EXPECT_EQ(c.pipeline.grid_rows, 5);

  // keys the config sets win
  StereoConfig d = default_stereo_config();
  apply_camera_defaults(
      YAML::Load("frontend:\n  stereo:\n    max_depth_m: 10.0\nmeasurement:\n  max_depth: 30.0\n"), rig, d);
  EXPECT_DOUBLE_EQ(d.frontend.stereo.max_depth_m, default_stereo_config().frontend.stereo.max_depth_m);
  EXPECT_DOUBLE_EQ(d.measurement.max_depth, default_stereo_config().measurement.max_depth);
}

}  // namespace
}  // namespace glmbslam::app
