// `glmbslam run PATH_TO_victoria_park/` with the multi-hypothesis importance density: phd3 (PHD-SLAM 3.0) and
// glmb-mh on the first 300 scans track GPS better than dead reckoning and write a map; the algorithm aliases
// are accepted and unknown names rejected.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/run_options.hpp"
#include "app/victoria_park_config.hpp"
#include "core/config_node.hpp"
#include "core/error.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

nlohmann::json run_vp(const std::filesystem::path& data, const std::filesystem::path& out,
                      const std::string& algorithm, std::size_t frames) {
  RunOptions o;
  o.dataset = data.string();
  o.out_dir = out.string();
  o.algorithm = algorithm;
  o.particles = 1;
  o.seed = 0;
  o.last_frame = frames;
  EXPECT_EQ(run_victoria_park(o), 0);
  std::ifstream in(out / "metrics.json");
  return nlohmann::json::parse(in);
}

TEST(VictoriaParkMh, Phd3AndGlmbMhOnAPrefixBeatDeadReckoning) {
  GLMBSLAM_REQUIRE_DATA(data, "victoria_park");
  const auto dir = test::fresh_temp_dir("vp_mh");
  const nlohmann::json dr = run_vp(data, dir / "dr", "dr", 300);
  for (const char* algorithm : {"phd3", "glmb_mh"}) {
    const nlohmann::json m = run_vp(data, dir / algorithm, algorithm, 300);
    EXPECT_EQ(m["frames"], 300);
    EXPECT_LT(m["position_rmse_m"].get<double>(), dr["position_rmse_m"].get<double>()) << algorithm;
    EXPECT_GT(m["map"]["landmarks"].get<int>(), 20) << algorithm;
  }
  RunOptions bad;
  bad.dataset = data.string();
  bad.out_dir = (dir / "bad").string();
  bad.algorithm = "phd9";
  EXPECT_THROW(run_victoria_park(bad), ConfigError);
  std::filesystem::remove_all(dir);
}

TEST(VictoriaParkMh, ThePhd3SectionDefaultsToThePublishedSettings) {
  VictoriaParkConfig c = default_victoria_park_config();
  EXPECT_EQ(c.phd3.proposal, "mh");
  EXPECT_EQ(c.phd3.likelihood, "poisson");
  EXPECT_EQ(c.phd.proposal, "prior");
  load_victoria_park_config(std::string(GLMBSLAM_SOURCE_DIR) + "/config/victoria_park.yaml", c);
  const VictoriaParkConfig d = default_victoria_park_config();
  EXPECT_EQ(c.phd3.proposal, d.phd3.proposal);
  EXPECT_EQ(c.phd3.likelihood, d.phd3.likelihood);
  EXPECT_EQ(c.phd3.resampling, d.phd3.resampling);
  EXPECT_DOUBLE_EQ(c.phd3.ess_threshold, d.phd3.ess_threshold);
  EXPECT_DOUBLE_EQ(c.phd3.existence_threshold, d.phd3.existence_threshold);
  EXPECT_EQ(c.rbpf.resampling, d.rbpf.resampling);
  EXPECT_DOUBLE_EQ(c.rbpf.ess_threshold, d.rbpf.ess_threshold);
  EXPECT_EQ(d.mh.single_particle, "mean");
  EXPECT_EQ(c.mh.single_particle, d.mh.single_particle);
  VictoriaParkConfig e;
  EXPECT_THROW(load_victoria_park_config(ConfigNode::parse("phd3:\n  proposal: optimal\n", "t"), e),
               ConfigError);
}

}  // namespace
}  // namespace glmbslam::app
