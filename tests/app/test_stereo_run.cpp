// End to end: `glmbslam run` on a short rendered stereo sequence (frontend → VO → δ-GLMB-SLAM 2.0), its
// outputs, the accuracy of the trajectory and the map, graceful handling of bad frames, and bad input.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "app/run_options.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "eval/report.hpp"
#include "io/pcd_writer.hpp"
#include "io/trajectory_io.hpp"
#include "support/rendered_clip.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kFrames = test::kClipFrames;

/// One short rendered sequence (built-in trajectory, with depth) shared by the tests of this file.
class StereoRun : public ::testing::Test {
 protected:
  // every process writes its outputs under its own folder
  static void SetUpTestSuite() {
    ProgressReporter::set_enabled(false);
    clip_ = test::rendered_stereo_clip();
    root_ = fs::temp_directory_path() / ("glmbslam_test_stereo_run_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static fs::path sequence() { return clip_ / "sequences" / "00"; }
  static RunOptions options(const std::string& out) {
    RunOptions o;
    o.dataset = sequence().string();
    o.out_dir = (root_ / out).string();
    o.particles = 3;
    return o;
  }
  static std::size_t count_lines(const fs::path& p) {
    std::ifstream in(p);
    std::size_t n = 0;
    std::string line;
    while (std::getline(in, line)) n += line.empty() ? 0 : 1;
    return n;
  }
  static fs::path root_;
  static fs::path clip_;
};
fs::path StereoRun::root_;
fs::path StereoRun::clip_;

TEST_F(StereoRun, WritesEveryOutputAndBeatsBoundsFromTheRendererNoise) {
  const RunOptions o = options("run");
  ASSERT_EQ(run_stereo(o), 0);
  const fs::path out(o.out_dir);
  for (const char* f :
       {"trajectory.txt", "vo_trajectory.txt", "map.pcd", "metrics.json", "config_used.yaml"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  EXPECT_TRUE(fs::exists(out / "plots" / "map_top.png"));
  EXPECT_TRUE(fs::exists(out / "plots" / "slam" / "trajectory_top.png"));
  EXPECT_EQ(io::read_kitti_poses((out / "trajectory.txt").string()).size(), kFrames);
  EXPECT_EQ(io::read_kitti_poses((out / "vo_trajectory.txt").string()).size(), kFrames);

  std::ifstream in(out / "metrics.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["frames"].get<int>(), static_cast<int>(kFrames));
  // ground_truth.txt is the reference metrics.json was computed against: evaluating the written files again
  // (what `glmbslam eval` or another tool does) gives the same figures
  const PoseList written_gt = io::read_kitti_poses((out / "ground_truth.txt").string());
  ASSERT_EQ(written_gt.size(), kFrames);
  const eval::TrajectoryEvaluation again =
      eval::evaluate_trajectory(written_gt, io::read_kitti_poses((out / "trajectory.txt").string()));
  EXPECT_NEAR(again.ate.se3_rmse_m, j["slam"]["ate"]["se3_rmse_m"].get<double>(), 1e-6);
  EXPECT_NEAR(again.kitti_short.t_rel_percent, j["slam"]["kitti_short"]["t_rel_percent"].get<double>(), 1e-4);
  // The renderer's images carry σ = 2 grey-level noise; features localise to well under a pixel, so over the
  // ~36 m of this clip frame-to-frame errors of a few millimetres accumulate to at most a few centimetres.
  // 0.25 m (0.7 % of the path) is a generous bound that a broken pipeline (wrong scale, sign, frame) misses.
  const double slam_ate = j["slam"]["ate"]["se3_rmse_m"].get<double>();
  const double vo_ate = j["vo"]["ate"]["se3_rmse_m"].get<double>();
  EXPECT_LT(slam_ate, 0.25);
  EXPECT_LT(vo_ate, 0.25);
  EXPECT_GT(j["map"]["landmarks"].get<int>(), 50);
  EXPECT_GT(j["filter"]["ess_percent"].get<double>(), 0.0);
  EXPECT_TRUE(j["timing"].contains("fps"));
  // the renderer's pairs are row-aligned: the run's alignment check finds no offset
  ASSERT_TRUE(j.contains("rectification"));
  EXPECT_GT(j["rectification"]["samples"].get<double>(), 50.0);
  EXPECT_LT(j["rectification"]["corner_max_px"].get<double>(), 0.1);
  // each rendered camera draws its own exposure (log σ 0.04): the contrast ratio is estimated on every frame
  // and scatters about 1
  ASSERT_TRUE(j.contains("stereo_photometry"));
  EXPECT_EQ(j["stereo_photometry"]["frames"].get<double>(), static_cast<double>(kFrames));
  EXPECT_EQ(j["stereo_photometry"]["compensated"].get<double>(), 1.0);
  EXPECT_NEAR(j["stereo_photometry"]["right_gain_median"].get<double>(), 1.0, 0.05);
  EXPECT_LT(j["stereo_photometry"]["right_gain_min"].get<double>(), 1.0);
  EXPECT_GT(j["stereo_photometry"]["right_gain_max"].get<double>(), 1.0);

  // The map's landmarks lie on the rendered surfaces: compare each landmark's depth in the first frame whose
  // depth map sees it with the true depth at its pixel.
  const auto map = io::read_pcd_map((out / "map.pcd").string());
  const auto gt = io::read_kitti_poses((clip_ / "poses" / "00.txt").string());
  const double fx = 718.856, cx = 607.1928, cy = 185.2157;
  std::vector<double> errors;
  for (const auto& p : map) {
    for (std::size_t k = 0; k < gt.size(); ++k) {
      const Eigen::Vector3d c = gt[k].inverse() * p.position;
      if (c.z() < 1.0 || c.z() > 20.0) continue;
      const int u = static_cast<int>(std::lround(fx * c.x() / c.z() + cx));
      const int v = static_cast<int>(std::lround(fx * c.y() / c.z() + cy));
      if (u < 0 || v < 0 || u >= 1241 || v >= 376) continue;
      char name[32];
      std::snprintf(name, sizeof name, "%06zu.png", k);
      const cv::Mat depth = cv::imread((sequence() / "depth_0" / name).string(), cv::IMREAD_UNCHANGED);
      ASSERT_FALSE(depth.empty());
      const double truth = depth.at<std::uint16_t>(v, u) / 256.0;
      if (truth > 0.0) errors.push_back(std::abs(truth - c.z()));
      break;
    }
  }
  ASSERT_GT(errors.size(), 50u);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  // A single stereo observation at the median landmark depth (~10 m) has a depth σ of z²/(f·b)·√2 px ≈ 0.37
  // m; landmarks are seen many times, so their median error must be below that.
  EXPECT_LT(errors[errors.size() / 2], 0.37);
}

TEST_F(StereoRun, DefaultSingleParticleMeanIsDeterministicAndWithinTheBounds) {
  // The shipped default: one particle whose pose is the optimal-kernel proposal's mean (no draw, no
  // resampling).
  RunOptions a = options("single_a");
  a.particles.reset();
  RunOptions b = options("single_b");
  b.particles.reset();
  b.seed = 99;  // the Gibbs sampler's stream changes, the pose estimate must stay within the bounds
  ASSERT_EQ(run_stereo(a), 0);
  ASSERT_EQ(run_stereo(b), 0);
  for (const RunOptions* o : {&a, &b}) {
    std::ifstream in(fs::path(o->out_dir) / "metrics.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["particles"].get<int>(), 1);
    EXPECT_DOUBLE_EQ(j["filter"]["ess_percent"].get<double>(), 100.0);
    EXPECT_DOUBLE_EQ(j["filter"]["resampling_percent"].get<double>(), 0.0);
    EXPECT_LT(j["slam"]["ate"]["se3_rmse_m"].get<double>(), 0.25);  // the bound of the test above
    EXPECT_GT(j["map"]["landmarks"].get<int>(), 50);
  }
  RunOptions c = options("single_c");
  c.particles.reset();
  ASSERT_EQ(run_stereo(c), 0);  // same seed as a: same trajectory
  const auto ta = io::read_kitti_poses((fs::path(a.out_dir) / "trajectory.txt").string());
  const auto tc = io::read_kitti_poses((fs::path(c.out_dir) / "trajectory.txt").string());
  ASSERT_EQ(ta.size(), tc.size());
  for (std::size_t i = 0; i < ta.size(); ++i) EXPECT_TRUE(ta[i].isApprox(tc[i], 1e-12)) << "frame " << i;
}

TEST_F(StereoRun, UnreadableFrameFallsBackAndKeepsOnePosePerFrame) {
  const fs::path copy = root_ / "broken";
  fs::remove_all(copy);
  fs::create_directories(copy / "sequences");
  fs::copy(sequence(), copy / "sequences" / "00", fs::copy_options::recursive);
  {  // truncate one left image in the middle of the sequence
    const fs::path png = copy / "sequences" / "00" / "image_0" / "000010.png";
    const auto size = fs::file_size(png);
    fs::resize_file(png, size / 3);
  }
  RunOptions o = options("broken_run");
  o.dataset = (copy / "sequences" / "00").string();
  o.first_frame = 0;
  o.last_frame = 20;
  ASSERT_EQ(run_stereo(o), 0);
  EXPECT_EQ(io::read_kitti_poses((fs::path(o.out_dir) / "trajectory.txt").string()).size(), 20u);
  std::ifstream in(fs::path(o.out_dir) / "metrics.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["filter"]["missing_frames"].get<int>(), 1);
}

TEST_F(StereoRun, SameSeedSameTrajectoryWhateverTheThreadCount) {
  RunOptions a = options("threads1");
  a.last_frame = 12;
  RunOptions b = options("threads2");
  b.last_frame = 12;
  const int before = thread_count();
  set_thread_count(1);
  ASSERT_EQ(run_stereo(a), 0);
  set_thread_count(2);
  ASSERT_EQ(run_stereo(b), 0);
  set_thread_count(before);
  const auto ta = io::read_kitti_poses((fs::path(a.out_dir) / "trajectory.txt").string());
  const auto tb = io::read_kitti_poses((fs::path(b.out_dir) / "trajectory.txt").string());
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t i = 0; i < ta.size(); ++i) EXPECT_TRUE(ta[i].isApprox(tb[i], 1e-12)) << "frame " << i;
}

// The frontend computed up to FrameSource::kLookahead frames ahead on its worker (pipeline.overlap_frontend,
// the default) and inline on the caller give the same trajectory, an unreadable frame included.
TEST_F(StereoRun, FrontendAheadOrInlineSameTrajectory) {
  const fs::path copy = root_ / "broken_ahead";
  fs::remove_all(copy);
  fs::create_directories(copy / "sequences");
  fs::copy(sequence(), copy / "sequences" / "00", fs::copy_options::recursive);
  const fs::path png = copy / "sequences" / "00" / "image_0" / "000007.png";
  fs::resize_file(png, fs::file_size(png) / 3);
  std::string trajectories[2];
  for (int overlap = 0; overlap < 2; ++overlap) {
    RunOptions o = options(overlap ? "ahead" : "inline");
    o.dataset = (copy / "sequences" / "00").string();
    o.last_frame = 14;
    const fs::path cfg = root_ / (overlap ? "ahead.yaml" : "inline.yaml");
    std::ofstream(cfg) << "pipeline:\n  overlap_frontend: " << (overlap ? "true" : "false") << "\n";
    o.config_file = cfg.string();
    ASSERT_EQ(run_stereo(o), 0);
    std::ifstream in(fs::path(o.out_dir) / "trajectory.txt");
    trajectories[overlap].assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    std::ifstream m(fs::path(o.out_dir) / "metrics.json");
    EXPECT_EQ(nlohmann::json::parse(m)["filter"]["missing_frames"].get<int>(), 1);
  }
  EXPECT_EQ(count_lines(root_ / "ahead" / "trajectory.txt"), 14u);
  EXPECT_EQ(trajectories[0], trajectories[1]);
}

TEST_F(StereoRun, BadInputIsAClearError) {
  RunOptions o = options("bad");
  o.first_frame = 30;
  o.last_frame = 100;  // beyond the sequence
  EXPECT_THROW(run_stereo(o), InputError);

  const fs::path copy = root_ / "badcalib";
  fs::remove_all(copy);
  fs::create_directories(copy);
  fs::copy(sequence(), copy / "00", fs::copy_options::recursive);
  std::ofstream(copy / "00" / "calib.txt") << "P0: 1 2 3\n";
  RunOptions c = options("badcalib_run");
  c.dataset = (copy / "00").string();
  try {
    run_stereo(c);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("calib.txt"), std::string::npos) << e.what();
  }

  RunOptions d = options("badconfig_run");
  const fs::path cfg = root_ / "typo.yaml";
  std::ofstream(cfg) << "rbpf:\n  partcles: 3\n";
  d.config_file = cfg.string();
  EXPECT_THROW(run_stereo(d), ConfigError);
}

}  // namespace
}  // namespace glmbslam::app
