// End to end: `glmbslam run --refine ml` (RFS-ML refinement of the stereo filter, paper 004) on the short
// rendered stereo clip: it writes the refined trajectory and map and a `refined` block beside `slam` and
// `vo`, its settings come from the config's `refine` section, and it is refused where there is no filter
// (vo).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/run_options.hpp"
#include "core/error.hpp"
#include "core/progress.hpp"
#include "io/trajectory_io.hpp"
#include "support/rendered_clip.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

class StereoRefine : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ProgressReporter::set_enabled(false);
    clip_ = test::rendered_stereo_clip();
    root_ = fs::temp_directory_path() / ("glmbslam_test_stereo_refine_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static RunOptions options(const std::string& out) {
    RunOptions o;
    o.dataset = (clip_ / "sequences" / "00").string();
    o.out_dir = (root_ / out).string();
    o.refine = "ml";
    return o;
  }
  /// Runs `o` with `yaml` as its config file (written to `name`.yaml) and returns its metrics.json.
  static nlohmann::json run_with_config(RunOptions& o, const std::string& name, const std::string& yaml) {
    const fs::path cfg = root_ / (name + ".yaml");
    std::ofstream(cfg) << yaml;
    o.config_file = cfg.string();
    EXPECT_EQ(run_stereo(o), 0);
    std::ifstream in(fs::path(o.out_dir) / "metrics.json");
    return nlohmann::json::parse(in);
  }
  /// Writes `yaml` to `o`'s config file and expects run_stereo to throw a ConfigError naming `key`.
  static void expect_config_error(const RunOptions& o, const std::string& yaml, const std::string& key) {
    std::ofstream(o.config_file) << yaml;
    try {
      run_stereo(o);
      FAIL() << "expected ConfigError for " << key;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  static fs::path root_;
  static fs::path clip_;
};
fs::path StereoRefine::root_;
fs::path StereoRefine::clip_;

TEST_F(StereoRefine, WritesTheRefinedTrajectoryMapAndMetrics) {
  const RunOptions o = options("ml");
  ASSERT_EQ(run_stereo(o), 0);
  std::ifstream in(fs::path(o.out_dir) / "metrics.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(io::read_kitti_poses((fs::path(o.out_dir) / "trajectory_refined.txt").string()).size(),
            test::kClipFrames);
  EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / "map_refined.pcd"));
  EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / "plots" / "refined"));
  // the same metric keys as slam and vo
  for (const auto& [key, value] : j["slam"].items()) EXPECT_TRUE(j["refined"].contains(key)) << key;
  const double refined = j["refined"]["ate"]["se3_rmse_m"].get<double>();
  const double vo = j["vo"]["ate"]["se3_rmse_m"].get<double>();
  // the refinement maximises the likelihood of the VO controls and the measurements: it stays near the VO it
  // starts from (a diverging solve is off by metres)
  EXPECT_LT(refined, 1.5 * vo + 0.01) << "VO " << vo;
  EXPECT_GT(j["refinement"]["windows"].get<double>(), 0.0);
  EXPECT_GT(j["refinement"]["final_log_likelihood_gain"].get<double>(), 0.0);
  EXPECT_GT(j["map"]["refined_landmarks"].get<int>(), 50);
  // measurement.pixel_sigma auto (the default): the final pass's σ, the median of the filter's per-frame σ,
  // is reported and lies within the clamp of the estimate (pixel_sigma_floor / _ceiling defaults)
  ASSERT_TRUE(j["refinement"].contains("final_pixel_sigma"));
  EXPECT_GE(j["refinement"]["final_pixel_sigma"].get<double>(), 0.3);
  EXPECT_LE(j["refinement"]["final_pixel_sigma"].get<double>(), 2.0);
}

TEST_F(StereoRefine, AFixedPixelSigmaIsTheFinalPassSigma) {
  RunOptions o = options("fixed_sigma");
  o.last_frame = 8;
  const nlohmann::json j = run_with_config(o, "fixed_sigma", "measurement:\n  pixel_sigma: 0.8\n");
  EXPECT_TRUE(j["refinement"].contains("final_ms"));
  EXPECT_NEAR(j["refinement"]["final_pixel_sigma"].get<double>(), 0.8, 1e-12);  // nothing estimated
}

TEST_F(StereoRefine, ReadsTheRefineSectionAndRejectsBadValues) {
  RunOptions o = options("config");
  o.refine.clear();  // enabled from the config
  o.last_frame = 8;
  const nlohmann::json j =
      run_with_config(o, "refine", "refine:\n  enabled: true\n  window: 4\n  every: 2\n  final: false\n");
  EXPECT_EQ(j["refinement"]["windows"].get<double>(), 4.0);  // frames 2, 4, 6, 8
  EXPECT_FALSE(j["refinement"].contains("final_ms"));
  expect_config_error(o, "refine:\n  window: 1\n", "window");
  expect_config_error(o, "refine:\n  mlslam:\n    max_round: 3\n", "max_round");
}

// refine.final_start: the final pass starts from the online windows' trajectory (the default) or from the
// filter's; without windows both are the filter's start, so the refined outputs are identical.
TEST_F(StereoRefine, TheFinalPassStartsFromTheWindowsOrTheFilter) {
  auto refined_of = [&](const std::string& name, const std::string& yaml) {
    RunOptions o = options(name);
    o.last_frame = 12;
    const nlohmann::json j = run_with_config(o, name, yaml);
    EXPECT_TRUE(j["refinement"].contains("final_ms")) << name;
    EXPECT_LT(j["refined"]["ate"]["se3_rmse_m"].get<double>(),
              1.5 * j["vo"]["ate"]["se3_rmse_m"].get<double>() + 0.01)
        << name;
    std::ifstream in(fs::path(o.out_dir) / "trajectory_refined.txt");
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string from_windows = refined_of("start_windows", "refine:\n  window: 6\n  every: 3\n");
  const std::string from_filter =
      refined_of("start_filter", "refine:\n  window: 6\n  every: 3\n  final_start: filter\n");
  EXPECT_NE(from_windows, from_filter);  // the windows moved the start, so the pass ends elsewhere
  const std::string no_window_default = refined_of("no_window_windows", "refine:\n  window: 0\n");
  const std::string no_window_filter =
      refined_of("no_window_filter", "refine:\n  window: 0\n  final_start: filter\n");
  EXPECT_EQ(no_window_default, no_window_filter);
  RunOptions o = options("bad_start");
  o.last_frame = 4;
  o.config_file = (root_ / "bad_start.yaml").string();
  expect_config_error(o, "refine:\n  final_start: vo\n", "final_start");
}

TEST_F(StereoRefine, IsRefusedWithoutAFilter) {
  RunOptions o = options("vo");
  o.algorithm = "vo";
  try {
    run_stereo(o);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("vo"), std::string::npos) << e.what();
  }
  o.algorithm.reset();
  o.refine = "icp";
  EXPECT_THROW(run_stereo(o), ConfigError);
}

}  // namespace
}  // namespace glmbslam::app
