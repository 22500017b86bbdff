// End to end on short rendered sequences with what real recordings do: a still camera, a stop in the middle
// of a drive, duplicated and dropped frames (timestamps kept), and the small-baseline EuRoC rig. The rendered
// ground truth is exact; the bounds come from the clean run of the same clip.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "app/run_options.hpp"
#include "core/progress.hpp"
#include "io/trajectory_io.hpp"
#include "sim/default_trajectory.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "support/test_data.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

class RealWorldSequences : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ProgressReporter::set_enabled(false); }
  void SetUp() override { root_ = test::fresh_temp_dir("realworld"); }
  void TearDown() override { fs::remove_all(root_); }

  /// Renders `poses` (or the built-in trajectory's frames `frames` when poses is empty) into root/name.
  fs::path render(const std::string& name, const PoseList& poses, const std::string& frames = "",
                  const std::string& calibration = "kitti00-02", std::size_t duplicate_every = 0,
                  std::size_t drop_every = 0, double rate = 10.0) {
    sim::SequenceRenderOptions o;
    o.out_dir = (root_ / name).string();
    if (!poses.empty()) {
      o.poses_path = (root_ / (name + "_poses.txt")).string();
      io::write_kitti_poses(o.poses_path, poses);
    }
    o.frames = frames;
    o.calibration = calibration;
    o.duplicate_every = duplicate_every;
    o.drop_every = drop_every;
    o.frame_rate = rate;
    sim::render_kitti_sequence(o);
    return root_ / name / "sequences" / "00";
  }
  /// Runs the default stereo pipeline (or with the YAML `config`); returns metrics.json.
  nlohmann::json run(const fs::path& sequence, const std::string& name, const std::string& config = "") {
    RunOptions o;
    o.dataset = sequence.string();
    o.out_dir = (root_ / (name + "_out")).string();
    if (!config.empty()) {
      o.config_file = (root_ / (name + ".yaml")).string();
      std::ofstream(o.config_file) << config;
    }
    EXPECT_EQ(run_stereo(o), 0);
    std::ifstream in(root_ / (name + "_out") / "metrics.json");
    return nlohmann::json::parse(in);
  }
  PoseList trajectory(const std::string& name, const char* file = "trajectory.txt") {
    return io::read_kitti_poses((root_ / (name + "_out") / file).string());
  }
  fs::path root_;
};

// A camera standing still: every frame is a measurement of zero motion, none is a repeat (the rendered noise
// differs from frame to frame), and the SLAM stays within 2 cm of the start.
TEST_F(RealWorldSequences, StillCameraStaysPut) {
  const fs::path seq = render("still", PoseList(30, Pose3::Identity()));
  const nlohmann::json j = run(seq, "still");
  EXPECT_EQ(j["filter"]["vo_fallback_frames"].get<int>(), 0);
  const PoseList path = trajectory("still");
  ASSERT_EQ(path.size(), 30u);
  for (std::size_t k = 0; k < path.size(); ++k)
    EXPECT_LT(path[k].translation().norm(), 0.02) << "frame " << k;
}

// The same still camera with a control covariance of 0.5 m / 0.02 rad on every frame (a constant-velocity
// fallback's floor): the wide prior widens the proposal's search, and the map still pins the pose (before the
// proposal's association rounds, optimal_proposal.hpp: 0.4 m within 5 frames, metres over 100).
TEST_F(RealWorldSequences, StillCameraUnderAWideControlCovariance) {
  const fs::path seq = render("still_wide", PoseList(30, Pose3::Identity()));
  run(seq, "still_wide", "motion:\n  min_sigma_translation: 0.5\n  min_sigma_rotation: 0.02\n");
  const PoseList path = trajectory("still_wide");
  ASSERT_EQ(path.size(), 30u);
  for (std::size_t k = 0; k < path.size(); ++k)
    EXPECT_LT(path[k].translation().norm(), 0.03) << "frame " << k;
}

// A drive that stops for 20 frames: the SLAM holds still while stopped (within 1 cm a frame), stays within
// the bound of the clean clip (test_stereo_run.cpp: 0.25 m over a few dozen frames) and is not worse than its
// VO. The backend's keypoint noise is the sequence's own (measurement.pixel_sigma auto: estimated from the
// VO's residuals; the still frames are not used for it): SLAM ATE 0.021 m vs VO 0.025 m (0.019 m at a
// fixed 1 px).
TEST_F(RealWorldSequences, StopAndGo) {
  const PoseList drive = sim::default_trajectory(10.0);
  PoseList poses(drive.begin(), drive.begin() + 15);
  poses.insert(poses.end(), 20, drive[14]);
  poses.insert(poses.end(), drive.begin() + 15, drive.begin() + 30);
  const fs::path seq = render("stop", poses);
  const nlohmann::json j = run(seq, "stop");
  const PoseList path = trajectory("stop");
  ASSERT_EQ(path.size(), poses.size());
  for (std::size_t k = 15; k < 34; ++k)
    EXPECT_LT((path[k + 1].translation() - path[k].translation()).norm(), 0.01) << "stopped frame " << k;
  EXPECT_LT(j["slam"]["ate"]["se3_rmse_m"].get<double>(), 0.25);
  EXPECT_LE(j["slam"]["ate"]["se3_rmse_m"].get<double>(), j["vo"]["ate"]["se3_rmse_m"].get<double>());
  EXPECT_EQ(j["filter"]["vo_fallback_frames"].get<int>(), 0);
}

// Every 10th frame a byte-identical repeat (zero motion), or every 10th frame left out (the timestamps show
// the gap; the prediction spans it): the SLAM's error stays within 10 % of the clean run's (+1 cm).
TEST_F(RealWorldSequences, DuplicatedAndDroppedFrames) {
  const nlohmann::json clean = run(render("clean", {}, "0:40"), "clean");
  const nlohmann::json duplicated = run(render("dup", {}, "0:40", "kitti00-02", 10), "dup");
  const nlohmann::json dropped = run(render("drop", {}, "0:44", "kitti00-02", 0, 10), "drop");
  const double base = clean["slam"]["ate"]["se3_rmse_m"].get<double>();
  EXPECT_LT(duplicated["slam"]["ate"]["se3_rmse_m"].get<double>(), 1.1 * base + 0.01);
  EXPECT_LT(dropped["slam"]["ate"]["se3_rmse_m"].get<double>(), 1.1 * base + 0.01);
  EXPECT_EQ(duplicated["filter"]["vo_fallback_frames"].get<int>(), 0);
  EXPECT_EQ(dropped["filter"]["vo_fallback_frames"].get<int>(), 0);
  // the duplicated frames carry the previous pose exactly as the ground truth does
  const PoseList path = trajectory("dup");
  for (std::size_t k = 10; k < path.size(); k += 10)
    EXPECT_LT((path[k].translation() - path[k - 1].translation()).norm(), 0.005) << "frame " << k;
}

// Ten black frames in a drive (a covered lens, a dark tunnel): the VO falls back to constant velocity over
// them, the filter moves its pose and keeps its map (a frame that sees nothing is not evidence that the
// landmarks left; unit tests: GlmbSlam/LmbSlam ABlindStep…), and the first frame after them is tracked
// against the last one that saw. Where the constant-velocity prediction holds, the pose after the dark is as
// good as in the clean clip: within 5 cm of the clean run's error 1 m after the stretch, and the path's ATE
// within 5 cm once the dark frames, whose poses nothing measured, are left out.
TEST_F(RealWorldSequences, DarkFramesKeepTheMapAndTheTrack) {
  const fs::path clean_seq = render("light", {}, "0:50");
  const fs::path seq = root_ / "dark";
  fs::copy(clean_seq, seq, fs::copy_options::recursive);
  const cv::Mat black = cv::Mat::zeros(cv::imread((seq / "image_0" / "000000.png").string()).size(), CV_8U);
  for (int k = 25; k < 35; ++k) {
    char name[16];
    std::snprintf(name, sizeof(name), "%06d.png", k);
    cv::imwrite((seq / "image_0" / name).string(), black);
    cv::imwrite((seq / "image_1" / name).string(), black);
  }
  const nlohmann::json clean = run(clean_seq, "light");
  const nlohmann::json dark = run(seq, "dark");
  EXPECT_EQ(dark["filter"]["vo_fallback_frames"].get<int>(), 10);
  const PoseList truth = io::read_kitti_poses((root_ / "light" / "poses" / "00.txt").string());
  const PoseList a = trajectory("light"), b = trajectory("dark");
  ASSERT_EQ(b.size(), truth.size());
  auto error = [&](const PoseList& path, std::size_t k) {
    return (path[k].translation() - truth[k].translation()).norm();
  };
  EXPECT_LT(error(b, 35), error(a, 35) + 0.05);
  double sum_a = 0.0, sum_b = 0.0;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (k >= 25 && k < 35) continue;
    sum_a += error(a, k) * error(a, k);
    sum_b += error(b, k) * error(b, k);
  }
  EXPECT_LT(std::sqrt(sum_b / 40.0), std::sqrt(sum_a / 40.0) + 0.05);
}

// The EuRoC rig (752×480, 0.11 m baseline, 20 Hz) on a slow indoor-like path: the camera-aware defaults make
// it run untuned, and the SLAM is not worse than its VO.
TEST_F(RealWorldSequences, SmallBaselineRig) {
  PoseList poses;
  for (int k = 0; k < 60; ++k) {
    const double t = k / 20.0;
    Pose3 T = Pose3::Identity();
    T.linear() = Eigen::AngleAxisd(0.15 * t, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.3 * std::sin(0.5 * t), 0.05 * std::sin(t), 0.4 * t);
    poses.push_back(T);
  }
  const nlohmann::json j = run(render("euroc", poses, "", "euroc", 0, 0, 20.0), "euroc");
  EXPECT_EQ(j["filter"]["vo_fallback_frames"].get<int>(), 0);
  EXPECT_LT(j["vo"]["ate"]["se3_rmse_m"].get<double>(), 0.05);
  EXPECT_LE(j["slam"]["ate"]["se3_rmse_m"].get<double>(),
            j["vo"]["ate"]["se3_rmse_m"].get<double>() * 1.1 + 0.002);
}

}  // namespace
}  // namespace glmbslam::app
