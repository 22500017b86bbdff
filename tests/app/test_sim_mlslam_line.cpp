// `glmbslam sim --scenario paper004_1d`: paper 004's 1D problem (Sec. VI-A). RFS-ML-SLAM from the odometry
// reaches the trajectory within centimetres and the five landmarks; with clutter it still does, where the
// vector ML solution with nearest-neighbour association keeps a landmark per clutter point and loses the
// trajectory (the paper's claim). The output does not depend on the thread count; the shipped config holds
// the built-in defaults.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "app/sim_runner.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

SimOptions paper004_1d(const std::filesystem::path& out, const std::string& config_text, double clutter) {
  SimOptions o;
  o.scenario = "paper004_1d";
  o.algorithm = "mlslam";
  o.runs = 5;  // paper 004: 5 Monte Carlo runs
  o.clutter = clutter;
  o.out_dir = out.string();
  std::filesystem::create_directories(out);
  o.config_file = (out / "config.yaml").string();
  std::ofstream(o.config_file) << config_text;
  return o;
}

TEST(SimMlSlamLine, RfsConvergesOnPaper004sOneDimensionalProblem) {
  const auto dir = test::fresh_temp_dir("sim_mlslam_line");
  const nlohmann::json m = run_simulation(paper004_1d(dir, "mlslam: {}\n", -1.0));
  EXPECT_NEAR(m["clutter_rate"].get<double>(), 0.055, 1e-12);  // 0.01 per metre over 0.5–6 m
  EXPECT_EQ(m["runs"], 5);
  // σ_z = 1 cm, odometry σ = 10 cm per step: dead reckoning wanders tens of centimetres
  EXPECT_LT(m["position_rmse_m"].get<double>(), 0.03);
  EXPECT_GT(m["dead_reckoning_rmse_per_run_m"]["mean"].get<double>(), 0.2);
  EXPECT_EQ(m["cardinality_error"]["mean"].get<double>(), 0.0);
  EXPECT_LT(m["map_ospa"]["distance_m"]["mean"].get<double>(), 0.02);
  EXPECT_EQ(m["position_error_per_step_m"].size(), 50u);
  EXPECT_TRUE(std::filesystem::exists(dir / "metrics.json"));
  EXPECT_TRUE(std::filesystem::exists(dir / "position_error.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "trajectory_map.png"));
  EXPECT_NE(summarize_simulation(m).find("position RMSE"), std::string::npos);
  // the shipped config/sim_paper004_1d.yaml documents exactly the scenario's built-in defaults
  SimOptions shipped = paper004_1d(dir / "shipped", "", -1.0);
  shipped.config_file = std::string(GLMBSLAM_SOURCE_DIR) + "/config/sim_paper004_1d.yaml";
  const nlohmann::json with_file = run_simulation(shipped);
  EXPECT_EQ(with_file["position_rmse_each_run_m"], m["position_rmse_each_run_m"]);
  EXPECT_EQ(with_file["ml"]["log_likelihood_each_run"], m["ml"]["log_likelihood_each_run"]);
}

TEST(SimMlSlamLine, WithClutterRfsHoldsWhereTheNearestNeighbourVectorSolutionDiverges) {
  const auto dir = test::fresh_temp_dir("sim_mlslam_line_clutter");
  const int threads = thread_count();
  set_thread_count(1);
  const nlohmann::json rfs = run_simulation(paper004_1d(dir / "rfs", "mlslam: {}\n", 2.0));
  set_thread_count(2);
  const nlohmann::json rfs2 = run_simulation(paper004_1d(dir / "rfs2", "mlslam: {}\n", 2.0));
  set_thread_count(threads);
  EXPECT_EQ(rfs["position_rmse_each_run_m"], rfs2["position_rmse_each_run_m"]);  // the same at any --threads
  EXPECT_EQ(rfs["ml"]["log_likelihood_each_run"], rfs2["ml"]["log_likelihood_each_run"]);
  // the baseline through the shipped config the workflow's comparison uses (config/sim_paper004_1d_nn.yaml)
  SimOptions vector_ml = paper004_1d(dir / "nn", "", 2.0);
  vector_ml.config_file = std::string(GLMBSLAM_SOURCE_DIR) + "/config/sim_paper004_1d_nn.yaml";
  const nlohmann::json nn = run_simulation(vector_ml);
  EXPECT_EQ(nn["association"], "nearest_neighbour");
  EXPECT_LT(rfs["position_rmse_m"].get<double>(), 0.1);
  EXPECT_EQ(rfs["cardinality_error"]["mean"].get<double>(), 0.0);
  EXPECT_GT(nn["cardinality_error"]["mean"].get<double>(), 20.0);
  EXPECT_GT(nn["position_rmse_m"].get<double>(), 5.0 * rfs["position_rmse_m"].get<double>());
}

TEST(SimMlSlamLine, OnlyTheStandaloneSolverRunsOnIt) {
  const auto dir = test::fresh_temp_dir("sim_mlslam_line_options");
  SimOptions o = paper004_1d(dir, "mlslam: {}\n", -1.0);
  o.algorithm = "glmb2";
  EXPECT_THROW(run_simulation(o), ConfigError);
  o.algorithm = "mlslam";
  o.refine = "ml";
  EXPECT_THROW(run_simulation(o), ConfigError);
}

TEST(SimMlSlam, OnPaper2019ItReportsTheFinalMapAndNoParticleFigures) {
  // RFS-ML from the odometry keeps no map per step and no particle weights: the per-step OSPA, ESS and
  // resampling are null (they were written as 0, "mean OSPA 0.000 m"), and the summary gives the final map's
  const auto dir = test::fresh_temp_dir("sim_mlslam_2019");
  SimOptions o = paper004_1d(dir, "mlslam: {}\n", -1.0);
  o.scenario = "paper2019";
  o.runs = 1;
  o.max_steps = 60;
  const nlohmann::json m = run_simulation(o);
  EXPECT_TRUE(m["ospa"]["mean_over_steps_m"].is_null());
  EXPECT_TRUE(m["ess_percent"].is_null());
  EXPECT_TRUE(m["resampling_percent"].is_null());
  EXPECT_GT(m["ospa"]["final_m"]["mean"].get<double>(), 0.0);
  const std::string line = summarize_simulation(m);
  EXPECT_NE(line.find("final-map OSPA"), std::string::npos) << line;
  EXPECT_EQ(line.find("ESS"), std::string::npos) << line;
  EXPECT_EQ(line.find("N="), std::string::npos) << line;
}

TEST(SimMlSlam, TheStandaloneSolveIsNotRefinedAgain) {
  // --algorithm mlslam is the RFS-ML solve itself: --refine ml with it is an error saying so, on every
  // scenario
  const auto dir = test::fresh_temp_dir("sim_mlslam_refine");
  SimOptions o = paper004_1d(dir, "mlslam: {}\n", -1.0);
  o.scenario = "paper2019";
  o.algorithm = "mlslam";
  o.refine = "ml";
  try {
    run_simulation(o);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--algorithm mlslam is the RFS-ML solve"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace glmbslam::app
