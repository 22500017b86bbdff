// Victoria Park pipeline: odometry → per-scan controls (zero-order hold), detections in the vehicle frame,
// seeded clutter, GPS error matching, the config file = the defaults in code, and runs on the real data
// (dead reckoning over the whole dataset, δ-GLMB-SLAM on a prefix).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/run_options.hpp"
#include "app/victoria_park_config.hpp"
#include "app/victoria_park_data.hpp"
#include "core/error.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

TEST(VictoriaParkData, ControlsHoldEachOdometrySampleUntilTheNextOrTheScan) {
  io::VictoriaParkOdometry odo;
  odo.time_s = {0.0, 1.0, 2.0, 3.0};
  odo.speed = {1.0, 2.0, 3.0, 4.0};
  odo.steering = {0.1, 0.2, 0.3, 0.4};
  const auto u = build_scan_controls(odo, 0.0, {0.5, 2.5, 2.5, 5.0});
  ASSERT_EQ(u.size(), 4u);
  ASSERT_EQ(u[0].cols(), 1);
  EXPECT_EQ(u[0].col(0), Eigen::Vector3d(1.0, 0.1, 0.5));
  ASSERT_EQ(u[1].cols(), 3);
  EXPECT_EQ(u[1].col(0), Eigen::Vector3d(1.0, 0.1, 0.5));
  EXPECT_EQ(u[1].col(1), Eigen::Vector3d(2.0, 0.2, 1.0));
  EXPECT_EQ(u[1].col(2), Eigen::Vector3d(3.0, 0.3, 0.5));
  EXPECT_EQ(u[2].cols(), 0);  // no time elapsed
  ASSERT_EQ(u[3].cols(), 2);
  EXPECT_EQ(u[3].col(0), Eigen::Vector3d(3.0, 0.3, 0.5));
  EXPECT_EQ(u[3].col(1), Eigen::Vector3d(4.0, 0.4, 2.0));  // the last sample is held to the scan
  // the pieces tile the intervals exactly
  const std::vector<double> times = {0.3, 0.7, 1.0, 1.9, 2.05, 3.5};
  const auto v = build_scan_controls(odo, 0.0, times);
  double prev = 0.0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    EXPECT_NEAR(v[k].row(2).sum(), times[k] - prev, 1e-12);
    prev = times[k];
  }
}

TEST(VictoriaParkData, DetectionsAreInTheVehicleFrameAndInTheFieldOfView) {
  io::LaserScan scan;
  scan.detections.resize(3, 5);
  scan.detections.col(0) << 10.0, M_PI / 2, 0.3;       // straight ahead
  scan.detections.col(1) << 20.0, M_PI, 0.2;           // left, 90° > 85°: out
  scan.detections.col(2) << 60.0, M_PI / 2, 0.2;       // beyond 50 m: out
  scan.detections.col(3) << 5.0, M_PI / 2 + 0.5, 0.4;  // 0.5 rad left
  scan.detections.col(4) << 5.0, 0.2, 0.4;             // 78.5° right (bearing − π/2 = −1.37)
  const VpMeasurementSet Z = scan_detections(scan, 50.0, 85.0 * M_PI / 180.0);
  ASSERT_EQ(Z.size(), 3u);
  EXPECT_NEAR(Z[0](1), 0.0, 1e-15);
  EXPECT_NEAR(Z[1](1), 0.5, 1e-15);
  EXPECT_NEAR(Z[2](1), 0.2 - M_PI / 2, 1e-15);
  EXPECT_EQ(Z[0](0), 10.0);
}

TEST(VictoriaParkData, ClutterIsSeededPoissonAndUniformOverTheFieldOfView) {
  ClutterOptions c;
  c.seed = 42;
  VpMeasurementSet a, b;
  append_clutter(c, 17, a);
  append_clutter(c, 17, b);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]);
  const int scans = 4000;
  double count = 0, mean_range = 0, mean_bearing = 0;
  for (int s = 0; s < scans; ++s) {
    VpMeasurementSet Z;
    append_clutter(c, static_cast<std::size_t>(s), Z);
    count += static_cast<double>(Z.size());
    for (const auto& z : Z) {
      EXPECT_GE(z(0), 0.0);
      EXPECT_LT(z(0), c.max_range);
      EXPECT_LE(std::abs(z(1)), c.half_fov);
      mean_range += z(0);
      mean_bearing += z(1);
    }
  }
  // Poisson(5): the mean of 4000 draws has std √(5/4000) ≈ 0.035
  EXPECT_NEAR(count / scans, 5.0, 0.15);
  EXPECT_NEAR(mean_range / count, 25.0, 0.5);
  EXPECT_NEAR(mean_bearing / count, 0.0, 0.05);
  c.rate = 0.0;
  VpMeasurementSet none;
  append_clutter(c, 3, none);
  EXPECT_TRUE(none.empty());
}

TEST(VictoriaParkData, GpsErrorsUseTheNearestFixWithinTheWindow) {
  std::vector<io::GpsFix> fixes(3);
  fixes[0].time_s = 1.00;
  fixes[0].position = Eigen::Vector2d(0, 0);
  fixes[1].time_s = 2.00;
  fixes[1].position = Eigen::Vector2d(10, 0);
  fixes[2].time_s = 2.03;
  fixes[2].position = Eigen::Vector2d(20, 0);
  const std::vector<double> t = {0.98, 1.5, 2.02, 2.06};
  const std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> p = {
      {3, 4}, {0, 0}, {20, 2}, {21, 0}};
  const GpsErrors e = gps_errors(fixes, t, p, 0.025);
  // 0.98 → fix 0 (5 m); 1.5 → none; 2.02 → fix 2 (nearer, 2 m); 2.06 → none (0.03 s away)
  ASSERT_EQ(e.error_m.size(), 2u);
  EXPECT_DOUBLE_EQ(e.error_m[0], 5.0);
  EXPECT_DOUBLE_EQ(e.error_m[1], 2.0);
  EXPECT_DOUBLE_EQ(e.rmse_m, std::sqrt((25.0 + 4.0) / 2.0));
}

TEST(VictoriaParkConfig, TheShippedFileDocumentsTheDefaults) {
  const VictoriaParkConfig d = default_victoria_park_config();
  VictoriaParkConfig c = default_victoria_park_config();
  c.rbpf.particles = 77;  // must be reset by the file
  load_victoria_park_config(std::string(GLMBSLAM_SOURCE_DIR) + "/config/victoria_park.yaml", c);
  EXPECT_EQ(c.algorithm, d.algorithm);
  EXPECT_LT((c.initial_pose - d.initial_pose).norm(), 1e-12);
  EXPECT_EQ(c.rbpf.particles, d.rbpf.particles);
  EXPECT_EQ(c.rbpf.resampling, d.rbpf.resampling);
  EXPECT_EQ(c.rbpf.glmb.gibbs_samples, d.rbpf.glmb.gibbs_samples);
  EXPECT_DOUBLE_EQ(c.rbpf.glmb.gate_threshold, d.rbpf.glmb.gate_threshold);
  EXPECT_DOUBLE_EQ(c.motion.wheel_base, 2.83);
  EXPECT_DOUBLE_EQ(c.motion.encoder_offset, 0.76);
  EXPECT_DOUBLE_EQ(c.motion.laser_forward, 3.78);
  EXPECT_DOUBLE_EQ(c.motion.laser_lateral, 0.5);
  EXPECT_NEAR(c.motion.sigma_steer, d.motion.sigma_steer, 1e-15);
  EXPECT_NEAR(c.measurement.sigma_bearing, d.measurement.sigma_bearing, 1e-15);
  EXPECT_NEAR(c.measurement.half_fov, 85.0 * M_PI / 180.0, 1e-15);
  EXPECT_DOUBLE_EQ(c.measurement.max_range, 50.0);
  EXPECT_DOUBLE_EQ(c.measurement.p_detect_inside, 0.7);
  EXPECT_DOUBLE_EQ(c.clutter_rate, 5.0);
  EXPECT_EQ(c.mh.max_assignments, 50);
  EXPECT_EQ(c.threads, d.threads);
  VictoriaParkConfig e;
  EXPECT_THROW(load_victoria_park_config(ConfigNode::parse("clutter: 5\n", "t"), e), ConfigError);
  EXPECT_THROW(load_victoria_park_config(ConfigNode::parse("algorithm: phd9\n", "t"), e), ConfigError);
}

nlohmann::json run(const std::filesystem::path& data, const std::filesystem::path& out,
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

TEST(VictoriaParkRun, DeadReckoningOverTheWholeDatasetDriftsAndSlamOnAPrefixTracksGps) {
  GLMBSLAM_REQUIRE_DATA(data, "victoria_park");
  const auto dir = test::fresh_temp_dir("vp");
  const nlohmann::json dr = run(data, dir / "dr", "deadreckoning", 0);
  EXPECT_EQ(dr["frames"], 7230);  // 7249 scans, 19 without any detection
  EXPECT_GT(dr["gps_fixes_used"].get<int>(), 1000);
  EXPECT_GT(dr["position_rmse_m"].get<double>(), 50.0);  // odometry alone drifts by ~150 m
  EXPECT_NEAR(dr["duration_s"].get<double>(), 1548.3, 1.0);
  std::ifstream traj(dir / "dr" / "trajectory.txt");
  int lines = 0;
  for (std::string l; std::getline(traj, l);) ++lines;
  EXPECT_EQ(lines, 7230);
  // δ-GLMB-SLAM on the first 300 scans (~64 s): close to GPS, better than dead reckoning there
  const nlohmann::json dr300 = run(data, dir / "dr300", "deadreckoning", 300);
  const nlohmann::json slam = run(data, dir / "glmb2", "glmb2", 300);
  EXPECT_EQ(slam["frames"], 300);
  EXPECT_GT(slam["gps_fixes_used"].get<int>(), 40);
  EXPECT_LT(slam["position_rmse_m"].get<double>(), 2.5);
  EXPECT_LT(slam["position_rmse_m"].get<double>(), dr300["position_rmse_m"].get<double>());
  EXPECT_GT(slam["map"]["landmarks"].get<int>(), 20);
  for (const char* f : {"metrics.json", "trajectory.txt", "map.txt", "map.pcd", "trajectory.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / "glmb2" / f)) << f;
  const nlohmann::json mh = run(data, dir / "mh", "glmb-mh", 300);
  EXPECT_LT(mh["position_rmse_m"].get<double>(), 2.5);
  std::filesystem::remove_all(dir);
}

// --refine ml keeps the filter's outputs and writes the refinement beside them: a refined block in
// metrics.json evaluated against the same GPS fixes, and the refined trajectory, map and errors.
TEST(VictoriaParkRun, RefinementIsWrittenBesideTheFilter) {
  GLMBSLAM_REQUIRE_DATA(data, "victoria_park");
  const auto dir = test::fresh_temp_dir("vp_refine");
  const nlohmann::json filter = run(data, dir / "filter", "glmb2", 200);
  RunOptions o;
  o.dataset = data.string();
  o.out_dir = (dir / "refined").string();
  o.algorithm = "glmb2";
  o.particles = 1;
  o.seed = 0;
  o.last_frame = 200;
  o.refine = "ml";
  ASSERT_EQ(run_victoria_park(o), 0);
  std::ifstream in(dir / "refined" / "metrics.json");
  const nlohmann::json m = nlohmann::json::parse(in);
  // the filter's figures are those of the run without refinement
  EXPECT_EQ(m["position_rmse_m"], filter["position_rmse_m"]);
  EXPECT_EQ(m["map"]["landmarks"], filter["map"]["landmarks"]);
  EXPECT_EQ(m["refine"], "ml");
  EXPECT_FALSE(m["interrupted"].get<bool>());
  ASSERT_TRUE(m.contains("refined"));
  const nlohmann::json& r = m["refined"];
  EXPECT_EQ(r["gps_fixes_used"], m["gps_fixes_used"]);
  EXPECT_GT(r["rounds"].get<int>(), 0);
  EXPECT_GT(r["log_likelihood_gain"].get<double>(), 0.0);
  EXPECT_FALSE(r["interrupted"].get<bool>());
  EXPECT_LT(r["position_rmse_m"].get<double>(), 2.5);
  EXPECT_GT(r["landmarks"].get<int>(), 20);
  for (const char* f : {"trajectory.txt", "map.txt", "map.pcd", "gps_errors.txt", "trajectory_refined.txt",
                        "map_refined.txt", "map_refined.pcd", "gps_errors_refined.txt", "report.html"})
    EXPECT_TRUE(std::filesystem::exists(dir / "refined" / f)) << f;
  auto read = [](const std::filesystem::path& p) {
    std::ifstream f(p);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  // trajectory.txt is the filter's, trajectory_refined.txt one line per step as well, and different
  EXPECT_EQ(read(dir / "refined" / "trajectory.txt"), read(dir / "filter" / "trajectory.txt"));
  const std::string refined = read(dir / "refined" / "trajectory_refined.txt");
  EXPECT_EQ(std::count(refined.begin(), refined.end(), '\n'), 200);
  EXPECT_NE(refined, read(dir / "filter" / "trajectory.txt"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace glmbslam::app
