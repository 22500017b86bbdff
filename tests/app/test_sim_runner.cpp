// `glmbslam sim` driver: metrics keys, plots, determinism across thread counts, option validation.
#include <filesystem>

#include <gtest/gtest.h>

#include "app/sim_runner.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

SimOptions small(const std::string& algorithm, const std::filesystem::path& out) {
  SimOptions o;
  o.scenario = "paper2019";
  o.algorithm = algorithm;
  o.particles = 4;
  o.runs = 3;
  o.clutter = 5.0;
  o.max_steps = 40;
  o.out_dir = out.string();
  return o;
}

TEST(SimRunner, WritesMetricsAndPlotsAndIsDeterministicAcrossThreadCounts) {
  for (const char* algorithm : {"glmb1", "phd1"}) {
    const auto dir = test::fresh_temp_dir(std::string("sim_runner_") + algorithm);
    set_thread_count(1);
    const nlohmann::json one = run_simulation(small(algorithm, dir / "one"));
    set_thread_count(2);
    SimOptions o = small(algorithm, dir / "two");
    o.plots = false;
    const nlohmann::json two = run_simulation(o);
    EXPECT_EQ(one["position_rmse_m"], two["position_rmse_m"]) << algorithm;
    EXPECT_EQ(one["heading_rmse_deg"], two["heading_rmse_deg"]) << algorithm;
    EXPECT_EQ(one["ospa"]["per_step_mean_m"], two["ospa"]["per_step_mean_m"]) << algorithm;
    EXPECT_EQ(one["rmse_per_step"]["x_m"].size(), 40u);
    EXPECT_EQ(one["rmse_per_step"]["x_m"][0], 0.0);  // the filters start at the true pose
    for (const char* key : {"position_rmse_m", "heading_rmse_deg", "ess_percent", "resampling_percent"}) {
      ASSERT_TRUE(one.contains(key)) << key;
      EXPECT_TRUE(std::isfinite(one[key].get<double>())) << key;
    }
    EXPECT_TRUE(one["ms_per_step"].contains("mean"));
    EXPECT_TRUE(one["cardinality_error"].contains("mean"));
    EXPECT_DOUBLE_EQ(one["resampling_percent"].get<double>(), 100.0);  // "always" by default
    for (const char* f :
         {"metrics.json", "trajectory_map.png", "rmse_xy.png", "rmse_heading.png", "ospa.png"}) {
      EXPECT_TRUE(std::filesystem::exists(dir / "one" / f)) << f;
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "two" / "ospa.png"));
    EXPECT_TRUE(std::filesystem::exists(dir / "two" / "metrics.json"));
  }
}

// phdslam3, 2 runs of its first 30 steps, 2 particles, no plots.
SimOptions phdslam3_short(const std::string& algorithm, const std::filesystem::path& dir) {
  SimOptions o;
  o.scenario = "phdslam3";
  o.algorithm = algorithm;
  o.particles = 2;
  o.runs = 2;
  o.max_steps = 30;
  o.plots = false;
  o.out_dir = dir.string();
  o.data_dir = test::shared_data_dir().string();
  return o;
}

TEST(SimRunner, PhdSlam3ReportsGospa) {
  GLMBSLAM_REQUIRE_DATA(data, "phdslam3_synthetic/Environment_SLAM.mat");
  const auto dir = test::fresh_temp_dir("sim_runner_phdslam3");
  SimOptions o = phdslam3_short("phd1", dir);
  const nlohmann::json m = run_simulation(o);
  ASSERT_TRUE(m.contains("gospa"));
  EXPECT_EQ(m["gospa"]["c_m"], 20.0);
  const double d = m["gospa"]["distance_m"]["mean"].get<double>();
  EXPECT_GE(d, 0.0);
  EXPECT_FALSE(m.contains("ospa"));
}

// --first-run R0: run R0 + i is the same run (data realisation and filter seed) whatever the first run.
TEST(SimRunner, FirstRunSelectsTheRealisations) {
  GLMBSLAM_REQUIRE_DATA(data, "phdslam3_synthetic/Environment_SLAM.mat");
  const auto dir = test::fresh_temp_dir("sim_runner_first_run");
  SimOptions o = phdslam3_short("glmb2", dir);
  const nlohmann::json both = run_simulation(o);
  o.first_run = 1;
  o.runs = 1;
  const nlohmann::json second = run_simulation(o);
  ASSERT_EQ(both["position_rmse_each_run_m"].size(), 2u);
  ASSERT_EQ(second["position_rmse_each_run_m"].size(), 1u);
  EXPECT_EQ(second["first_run"], 1);
  EXPECT_EQ(second["position_rmse_each_run_m"][0].get<double>(),
            both["position_rmse_each_run_m"][1].get<double>());
  EXPECT_NE(both["position_rmse_each_run_m"][0].get<double>(),
            both["position_rmse_each_run_m"][1].get<double>());
  o.first_run = -1;
  EXPECT_THROW(run_simulation(o), ConfigError);
}

TEST(SimRunner, RejectsBadOptions) {
  const auto dir = test::fresh_temp_dir("sim_runner_bad");
  SimOptions o = small("glmb1", dir);
  o.scenario = "nope";
  EXPECT_THROW(run_simulation(o), ConfigError);
  o = small("nope", dir);
  EXPECT_THROW(run_simulation(o), ConfigError);
  o = small("glmb1", dir);
  o.particles = 0;
  EXPECT_THROW(run_simulation(o), ConfigError);
  o = small("glmb1", dir);
  o.scenario = "phdslam3";
  o.data_dir = (dir / "missing").string();
  EXPECT_THROW(run_simulation(o), InputError);
}

}  // namespace
}  // namespace glmbslam::app
