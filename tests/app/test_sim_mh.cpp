// `glmbslam sim` with the multi-hypothesis importance density: glmb_mh (δ-GLMB map) and phd3 (PHD-SLAM 3.0)
// run on the paper2019 scenario, are deterministic across thread counts and beat dead reckoning.
#include <filesystem>

#include <gtest/gtest.h>

#include "app/sim_runner.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

SimOptions small_mh(const std::string& algorithm, const std::filesystem::path& out) {
  SimOptions o;
  o.scenario = "paper2019";
  o.algorithm = algorithm;
  o.particles = 4;
  o.runs = 2;
  o.clutter = 5.0;
  o.max_steps = 40;
  o.out_dir = out.string();
  o.plots = false;
  return o;
}

TEST(SimRunnerMh, GlmbMhAndPhd3AreDeterministicAcrossThreadCountsAndBeatDeadReckoning) {
  const int threads = thread_count();
  const auto dir = test::fresh_temp_dir("sim_runner_mh");
  const nlohmann::json dr = run_simulation(small_mh("dr", dir / "dr"));
  for (const char* algorithm : {"glmb_mh", "phd3"}) {
    set_thread_count(1);
    const nlohmann::json one = run_simulation(small_mh(algorithm, dir / (std::string(algorithm) + "1")));
    set_thread_count(2);
    const nlohmann::json two = run_simulation(small_mh(algorithm, dir / (std::string(algorithm) + "2")));
    EXPECT_EQ(one["algorithm"], algorithm);
    EXPECT_EQ(one["position_rmse_m"], two["position_rmse_m"]) << algorithm;
    EXPECT_EQ(one["ospa"]["per_step_mean_m"], two["ospa"]["per_step_mean_m"]) << algorithm;
    EXPECT_LT(one["position_rmse_m"].get<double>(), dr["position_rmse_m"].get<double>()) << algorithm;
  }
  set_thread_count(threads);
  SimOptions bad = small_mh("phd4", dir / "bad");
  EXPECT_THROW(run_simulation(bad), ConfigError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace glmbslam::app
