// `glmbslam sim --scenario phdslam3` with δ-GLMB-SLAM 2.0: the shipped config/sim_phdslam3.yaml equals the
// built-in phdslam3 defaults, and a short fixed-seed run keeps its position error at the level the sensor
// allows (regression for the weak-birth start, where the map inherited the motion noise of the first steps).
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "app/sim_runner.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

SimOptions phdslam3(const std::filesystem::path& out, int particles, int runs, std::size_t steps) {
  SimOptions o;
  o.scenario = "phdslam3";
  o.algorithm = "glmb2";
  o.particles = particles;
  o.runs = runs;
  o.max_steps = steps;
  o.plots = false;
  o.out_dir = out.string();
  o.data_dir = test::shared_data_dir().string();
  return o;
}

TEST(SimPhdSlam3, ShippedConfigEqualsBuiltInDefaults) {
  GLMBSLAM_REQUIRE_DATA(data, "phdslam3_synthetic/Environment_SLAM.mat");
  const auto dir = test::fresh_temp_dir("sim_phdslam3_config");
  // with the refinement, so the file's mlslam section is compared too
  SimOptions built_in = phdslam3(dir / "a", 3, 1, 80);
  built_in.refine = "ml";
  const nlohmann::json a = run_simulation(built_in);
  SimOptions with_file = phdslam3(dir / "b", 3, 1, 80);
  with_file.refine = "ml";
  with_file.config_file = std::string(GLMBSLAM_SOURCE_DIR) + "/config/sim_phdslam3.yaml";
  const nlohmann::json b = run_simulation(with_file);
  EXPECT_DOUBLE_EQ(a["position_rmse_m"].get<double>(), b["position_rmse_m"].get<double>());
  EXPECT_DOUBLE_EQ(a["heading_rmse_deg"].get<double>(), b["heading_rmse_deg"].get<double>());
  EXPECT_DOUBLE_EQ(a["gospa"]["distance_m"]["mean"].get<double>(),
                   b["gospa"]["distance_m"]["mean"].get<double>());
  EXPECT_DOUBLE_EQ(a["resampling_percent"].get<double>(), b["resampling_percent"].get<double>());
  // ESS-triggered resampling by default on this scenario (not every step)
  EXPECT_LT(a["resampling_percent"].get<double>(), 100.0);
}

TEST(SimPhdSlam3, Glmb2StaysWithinTheSensorNoiseOverTheFirst300Steps) {
  GLMBSLAM_REQUIRE_DATA(data, "phdslam3_synthetic/Environment_SLAM.mat");
  const auto dir = test::fresh_temp_dir("sim_phdslam3_300");
  const nlohmann::json m = run_simulation(phdslam3(dir / "glmb2", 10, 4, 300));
  SimOptions dr_options = phdslam3(dir / "dr", 1, 4, 300);
  dr_options.algorithm = "dr";
  const nlohmann::json dr = run_simulation(dr_options);
  // Dead reckoning drifts by metres to tens of metres over 300 steps (σ_v = 0.8 m and σ_ω = 0.5° per step).
  // With 6–12 landmarks in view, each measured to σ_r = 0.8 m and σ_b = 0.3° (0.8 m across at 150 m), SLAM
  // must stay within a few sensor standard deviations and far below dead reckoning.
  const double pos = m["position_rmse_m"].get<double>();
  EXPECT_LT(pos, 2.5 * 0.8);
  EXPECT_LT(pos, 0.2 * dr["position_rmse_m"].get<double>());
  EXPECT_LT(m["heading_rmse_deg"].get<double>(), 3.0 * 0.3);
  // every landmark seen so far is mapped once: at most one missing or extra per run on average
  EXPECT_LE(m["cardinality_error"]["mean_abs"].get<double>(), 1.0);
  // GOSPA (c = 20 m, p = 2): one missed or false landmark alone adds c²/2 = 200 m² (14.1 m)
  EXPECT_LT(m["gospa"]["distance_m"]["mean"].get<double>(), 20.0);
}

}  // namespace
}  // namespace glmbslam::app
