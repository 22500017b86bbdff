#include <filesystem>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "frontend/frontend_config.hpp"
#include "frontend/stereo_pose_refiner.hpp"
#include "support/test_data.hpp"

namespace glmbslam::frontend {
namespace {

TEST(FrontendConfig, ReadsValuesAndKeepsDefaults) {
  ConfigNode node = ConfigNode::parse(
      "orb: {features: 1000, levels: 4}\nvo: {min_inliers: 30, consensus_first: true}\n"
      "stereo: {subpixel_refine: lk, gain_compensation: false}\n",
      "test");
  const FrontendConfig c = load_frontend_config(node);
  EXPECT_EQ(c.orb.features, 1000);
  EXPECT_EQ(c.orb.levels, 4);
  EXPECT_DOUBLE_EQ(c.orb.scale_factor, 1.2);
  EXPECT_EQ(c.vo.min_inliers, 30);
  EXPECT_TRUE(c.vo.consensus_first);
  EXPECT_EQ(c.stereo.subpixel_refine, "lk");
  EXPECT_FALSE(c.stereo.gain_compensation);
  EXPECT_EQ(c.stereo.subpixel_cost, StereoMatchConfig{}.subpixel_cost);
  EXPECT_EQ(c.stereo.max_hamming, StereoMatchConfig{}.max_hamming);
}

TEST(FrontendConfig, UnknownKeyAndBadRangeAreErrors) {
  ConfigNode typo = ConfigNode::parse("orb: {featurs: 1000}\n", "test");
  EXPECT_THROW(load_frontend_config(typo), ConfigError);
  ConfigNode top = ConfigNode::parse("orbb: {}\n", "test");
  EXPECT_THROW(load_frontend_config(top), ConfigError);
  ConfigNode range = ConfigNode::parse("stereo: {min_depth_m: 50, max_depth_m: 10}\n", "test");
  EXPECT_THROW(load_frontend_config(range), ConfigError);
  ConfigNode type = ConfigNode::parse("vo: {ratio: fast}\n", "test");
  EXPECT_THROW(load_frontend_config(type), ConfigError);
  ConfigNode refiner = ConfigNode::parse("vo: {refiner: levenberg}\n", "test");
  EXPECT_THROW(load_frontend_config(refiner), ConfigError);
  ConfigNode subpixel = ConfigNode::parse("stereo: {subpixel_refine: parabola}\n", "test");
  EXPECT_THROW(load_frontend_config(subpixel), ConfigError);
}

TEST(FrontendConfig, RefinerChoiceReachesTheRefinementOptions) {
  ConfigNode node =
      ConfigNode::parse("vo: {refiner: gauss_newton, huber_delta: 3.0, refine_rounds: 4}\n", "test");
  const FrontendConfig c = load_frontend_config(node);
  const PoseRefinementOptions opt = pose_refinement_options(c.vo);
  EXPECT_EQ(opt.refiner, PoseRefinerKind::kGaussNewton);
  EXPECT_DOUBLE_EQ(opt.huber_delta, 3.0);
  EXPECT_EQ(opt.rounds, 4);
  EXPECT_EQ(pose_refinement_options(VoConfig{}).refiner, PoseRefinementOptions{}.refiner);
}

// config/frontend_defaults.yaml documents every key with the values in code.
TEST(FrontendConfig, DefaultsFileMatchesCode) {
  const auto path = std::filesystem::path(GLMBSLAM_SOURCE_DIR) / "config" / "frontend_defaults.yaml";
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  ConfigNode root = ConfigNode::load_file(path.string());
  ConfigNode node = root.child("frontend");
  const FrontendConfig c = load_frontend_config(node);
  root.finish();
  const FrontendConfig d;
  EXPECT_EQ(c.orb.features, d.orb.features);
  EXPECT_EQ(c.orb.levels, d.orb.levels);
  EXPECT_DOUBLE_EQ(c.orb.scale_factor, d.orb.scale_factor);
  EXPECT_EQ(c.orb.cell_size, d.orb.cell_size);
  EXPECT_DOUBLE_EQ(c.stereo.max_depth_m, d.stereo.max_depth_m);
  EXPECT_DOUBLE_EQ(c.stereo.pixel_sigma, d.stereo.pixel_sigma);
  EXPECT_EQ(c.stereo.max_hamming, d.stereo.max_hamming);
  EXPECT_EQ(c.stereo.subpixel_cost, d.stereo.subpixel_cost);
  EXPECT_EQ(c.stereo.subpixel_refine, d.stereo.subpixel_refine);
  EXPECT_EQ(c.stereo.gain_compensation, d.stereo.gain_compensation);
  EXPECT_DOUBLE_EQ(c.vo.search_radius_px, d.vo.search_radius_px);
  EXPECT_EQ(c.vo.refiner, d.vo.refiner);
  EXPECT_DOUBLE_EQ(c.vo.huber_delta, d.vo.huber_delta);
  EXPECT_EQ(c.vo.min_inliers, d.vo.min_inliers);
  EXPECT_EQ(c.vo.rematch_after_pnp, d.vo.rematch_after_pnp);
  EXPECT_EQ(c.vo.consensus_first, d.vo.consensus_first);
  EXPECT_DOUBLE_EQ(c.vo.fallback_sigma_translation_m, d.vo.fallback_sigma_translation_m);
}

}  // namespace
}  // namespace glmbslam::frontend
