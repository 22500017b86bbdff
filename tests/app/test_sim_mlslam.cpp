// `glmbslam sim` with RFS maximum-likelihood SLAM (paper 004): on paper 004's own 2D problem with clutter the
// RFS-ML solution converges to the trajectory and the map, where the map of the vector ML solution with
// nearest-neighbour association diverges (a landmark per clutter point); `--refine ml` does not worsen a
// filter's estimate.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "app/sim_runner.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

SimOptions paper004(const std::filesystem::path& out, const std::string& config_text) {
  SimOptions o;
  o.scenario = "paper004";
  o.algorithm = "mlslam";
  o.runs = 5;  // paper 004: 5 Monte Carlo runs
  o.clutter = 2.0;
  o.plots = false;
  o.out_dir = out.string();
  std::filesystem::create_directories(out);
  o.config_file = (out / "config.yaml").string();
  std::ofstream(o.config_file) << config_text;
  return o;
}

TEST(SimMlSlam, RfsConvergesWhereTheNearestNeighbourVectorMapDivergesOnPaper004WithClutter) {
  const auto dir = test::fresh_temp_dir("sim_mlslam_paper004");
  const nlohmann::json rfs = run_simulation(paper004(dir / "rfs", "mlslam: {}\n"));
  const nlohmann::json nn =
      run_simulation(paper004(dir / "nn", "mlslam:\n  association: nearest_neighbour\n"));
  // paper 004 Fig. 3: errors of a few cm at most, and the map size recovered
  EXPECT_LT(rfs["position_rmse_m"].get<double>(), 0.02);
  EXPECT_LE(std::abs(rfs["cardinality_error"]["mean"].get<double>()), 0.2);
  EXPECT_LT(rfs["gospa"]["distance_m"]["mean"].get<double>(), 5.0);
  // the vector solution keeps a landmark for every clutter point it cannot associate: its map diverges
  EXPECT_GT(nn["cardinality_error"]["mean"].get<double>(), 20.0);
  EXPECT_GT(nn["gospa"]["distance_m"]["mean"].get<double>(),
            10.0 * rfs["gospa"]["distance_m"]["mean"].get<double>());
}

TEST(SimMlSlam, RefinementDoesNotWorsenTheFilter) {
  const auto dir = test::fresh_temp_dir("sim_mlslam_refine");
  SimOptions o;
  o.scenario = "paper2019";
  o.algorithm = "glmb2";
  o.refine = "ml";
  o.particles = 2;
  o.runs = 2;
  o.max_steps = 60;
  o.plots = false;
  o.out_dir = (dir / "out").string();
  const nlohmann::json m = run_simulation(o);
  const double filter = m["ml"]["filter_position_rmse_per_run_m"]["mean"].get<double>();
  EXPECT_LE(m["position_rmse_per_run_m"]["mean"].get<double>(), filter);
  EXPECT_EQ(m["refine"], "ml");
  // the filter's per-run figures beside the refined ones are those of the same runs without refinement
  SimOptions plain = o;
  plain.refine.clear();
  plain.out_dir = (dir / "plain").string();
  const nlohmann::json p = run_simulation(plain);
  EXPECT_EQ(m["ml"]["filter_position_rmse_each_run_m"], p["position_rmse_each_run_m"]);
  EXPECT_FALSE(p.contains("ml"));
}

}  // namespace
}  // namespace glmbslam::app
