// End to end: `glmbslam run --algorithm lmb / lmb1` (LMB-SLAM behind the stereo pipeline's filter stage) on a
// short rendered stereo sequence: it completes, tracks the camera as closely as its VO control allows, maps
// the scene, and reads its settings from the config's `lmb` section.
#include <filesystem>
#include <fstream>
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

constexpr std::size_t kFrames = test::kClipFrames;

/// The rendered clip of the stereo end-to-end tests (tests/support/rendered_clip.hpp).
class StereoLmb : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ProgressReporter::set_enabled(false);
    clip_ = test::rendered_stereo_clip();
    root_ = fs::temp_directory_path() / ("glmbslam_test_stereo_lmb_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static RunOptions options(const std::string& out, const std::string& algorithm) {
    RunOptions o;
    o.dataset = (clip_ / "sequences" / "00").string();
    o.out_dir = (root_ / out).string();
    o.algorithm = algorithm;
    return o;
  }
  static nlohmann::json metrics(const RunOptions& o) {
    std::ifstream in(fs::path(o.out_dir) / "metrics.json");
    return nlohmann::json::parse(in);
  }
  static fs::path root_;
  static fs::path clip_;
};
fs::path StereoLmb::root_;
fs::path StereoLmb::clip_;

TEST_F(StereoLmb, OptimalProposalTracksAsWellAsItsVoControlAndMapsTheScene) {
  const RunOptions o = options("lmb", "lmb");  // the shipped default: one particle at the proposal mean
  ASSERT_EQ(run_stereo(o), 0);
  const nlohmann::json j = metrics(o);
  EXPECT_EQ(j["algorithm"].get<std::string>(), "lmb");
  EXPECT_EQ(j["frames"].get<int>(), static_cast<int>(kFrames));
  EXPECT_EQ(io::read_kitti_poses((fs::path(o.out_dir) / "trajectory.txt").string()).size(), kFrames);
  const double slam_ate = j["slam"]["ate"]["se3_rmse_m"].get<double>();
  const double vo_ate = j["vo"]["ate"]["se3_rmse_m"].get<double>();
  // The filter's pose is the optimal-kernel mean given the VO motion (its control) and the mapped landmarks:
  // a filter that tracks stays near the VO it starts from; one that loses the map or mis-associates drifts
  // off by metres within a few frames. Bound: the VO's ATE plus half of it (plus 1 cm for a VO that is
  // nearly exact on this clip).
  EXPECT_LT(slam_ate, 1.5 * vo_ate + 0.01) << "VO " << vo_ate;
  EXPECT_GT(j["map"]["landmarks"].get<int>(), 50);  // Bernoullis with existence above 0.5
}

TEST_F(StereoLmb, PriorProposalWithParticlesTracks) {
  RunOptions o = options("lmb1", "lmb1");
  o.particles = 3;
  o.last_frame = 20;
  ASSERT_EQ(run_stereo(o), 0);
  const nlohmann::json j = metrics(o);
  EXPECT_EQ(j["particles"].get<int>(), 3);
  EXPECT_GT(j["filter"]["ess_percent"].get<double>(), 0.0);
  const double slam_ate = j["slam"]["ate"]["se3_rmse_m"].get<double>();
  const double vo_ate = j["vo"]["ate"]["se3_rmse_m"].get<double>();
  // Poses drawn from the motion model (the VO covariance) and weighted by the map: the draws add noise of
  // the VO's own size per frame, so the bound is wider than the optimal proposal's.
  EXPECT_LT(slam_ate, 3.0 * vo_ate + 0.02) << "VO " << vo_ate;
  EXPECT_GT(j["map"]["landmarks"].get<int>(), 50);
}

TEST_F(StereoLmb, ReadsTheLmbSectionOfTheConfig) {
  const fs::path cfg = root_ / "lmb.yaml";
  // existences are at most 1: an estimate threshold of 1 leaves the map estimate (map.pcd) empty
  std::ofstream(cfg) << "pipeline:\n  algorithm: lmb\nlmb:\n  estimate_existence: 1.0\n";
  RunOptions o = options("lmb_config", "lmb");
  o.algorithm.reset();  // from the config
  o.config_file = cfg.string();
  o.last_frame = 5;
  ASSERT_EQ(run_stereo(o), 0);
  const nlohmann::json j = metrics(o);
  EXPECT_EQ(j["algorithm"].get<std::string>(), "lmb");
  EXPECT_EQ(j["map"]["landmarks"].get<int>(), 0);

  std::ofstream(cfg) << "lmb:\n  existance_threshold: 0.1\n";  // a typo is an error naming the key
  try {
    run_stereo(o);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("existance_threshold"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace glmbslam::app
