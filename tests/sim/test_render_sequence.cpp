// `glmbslam render` output: KITTI odometry layout, exact poses, determinism, bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "io/kitti_odometry.hpp"
#include "io/stereo_dataset.hpp"
#include "io/trajectory_io.hpp"
#include "sim/default_trajectory.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "sim/stereo_procedural_world.hpp"
#include "support/test_data.hpp"

namespace glmbslam::sim {
namespace {
namespace fs = std::filesystem;

void expect_same_poses(const PoseList& a, const PoseList& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_LT((a[i].matrix() - b[i].matrix()).cwiseAbs().maxCoeff(), tol) << "pose " << i;
  }
}

std::size_t count_lines(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) ++n;
  return n;
}

bool same_bytes(const fs::path& a, const fs::path& b) {
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(fa)), std::istreambuf_iterator<char>());
  const std::string sb((std::istreambuf_iterator<char>(fb)), std::istreambuf_iterator<char>());
  return !sa.empty() && sa == sb;
}

class RenderSequence : public ::testing::Test {
 protected:
  void SetUp() override { ProgressReporter::set_enabled(false); }
};

TEST_F(RenderSequence, DefaultTrajectoryReadsBackThroughTheKittiReader) {
  const fs::path out = test::fresh_temp_dir("render");
  SequenceRenderOptions o;
  o.out_dir = out.string();
  o.frames = "10:16";
  o.sequence = "07";
  o.seed = 4;
  o.movers = 2;
  o.depth = true;
  const SequenceRenderSummary summary = render_kitti_sequence(o);
  EXPECT_EQ(summary.frames, 6U);
  const fs::path seq = out / "sequences" / "07";
  ASSERT_TRUE(fs::is_regular_file(seq / "image_0" / "000005.png"));
  ASSERT_TRUE(fs::is_regular_file(seq / "depth_0" / "000005.png"));
  EXPECT_FALSE(fs::exists(seq / "image_0" / "000006.png"));
  EXPECT_EQ(count_lines(seq / "times.txt"), 6U);

  // Poses: the input frames 10..15, relative to frame 10.
  const PoseList all = default_trajectory();
  const PoseList expected = io::relative_to_first(PoseList(all.begin() + 10, all.begin() + 16));
  expect_same_poses(io::read_kitti_poses((out / "poses" / "07.txt").string()), expected, 1e-7);

  // Calibration: P1[0,3] = −fx·b, as KITTI.
  const StereoCalibration calib = io::read_kitti_odometry_calibration((seq / "calib.txt").string());
  const StereoCalibration named = named_kitti_calibration("kitti00-02");
  EXPECT_NEAR(calib.fx, named.fx, 1e-9);
  EXPECT_NEAR(calib.cx, named.cx, 1e-9);
  EXPECT_NEAR(calib.cy, named.cy, 1e-9);
  EXPECT_NEAR(calib.fx * calib.baseline, 386.1448, 1e-6);

  // Through the dataset interface (format detection, ground truth found at ../../poses/07.txt).
  const auto dataset = io::open_stereo_dataset(seq.string());
  ASSERT_EQ(dataset->size(), 6U);
  EXPECT_EQ(dataset->calibration().width, 1241);
  EXPECT_EQ(dataset->calibration().height, 376);
  EXPECT_NEAR(dataset->timestamps()[5], 0.5, 1e-9);
  ASSERT_TRUE(dataset->ground_truth().has_value());
  expect_same_poses(*dataset->ground_truth(), expected, 1e-7);

  // The stored images are the in-memory rendering of the same frame (frame index 12 of the trajectory).
  ProceduralWorldOptions wopt;
  wopt.seed = 4;
  wopt.movers = 2;
  const ProceduralWorld world(all, wopt);
  RenderOptions ropt;
  ropt.seed = 4;
  StereoRenderer renderer(world, named, ropt);
  RenderedFrame frame;
  renderer.render(all[12], 1.2, 12, frame);
  const io::StereoFrame loaded = dataset->load(2);
  EXPECT_EQ(cv::norm(loaded.left, frame.left, cv::NORM_L1), 0.0);
  EXPECT_EQ(cv::norm(loaded.right, frame.right, cv::NORM_L1), 0.0);
  // Depth PNG: metres·256.
  const cv::Mat d16 = cv::imread((seq / "depth_0" / "000002.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(d16.type(), CV_16UC1);
  for (int v = 200; v < 376; v += 41) {
    for (int u = 0; u < 1241; u += 97) {
      const float z = frame.depth.at<float>(v, u);
      if (z > 0.0f && z < 255.0f) {
        EXPECT_NEAR(d16.at<std::uint16_t>(v, u) / 256.0, z, 0.5 / 256.0 + 1e-6);
      }
    }
  }
  // No temporary folders left.
  for (const auto& entry : fs::directory_iterator(out / "sequences"))
    EXPECT_EQ(entry.path().filename(), "07");
}

TEST_F(RenderSequence, SameSeedGivesByteIdenticalFilesWhateverTheThreadCount) {
  const fs::path out = test::fresh_temp_dir("render");
  SequenceRenderOptions o;
  o.frames = "200:203";
  o.seed = 11;
  o.movers = 3;
  o.out_dir = (out / "a").string();
  set_thread_count(1);
  render_kitti_sequence(o);
  o.out_dir = (out / "b").string();
  set_thread_count(2);
  render_kitti_sequence(o);
  set_thread_count(0);
  for (const char* cam : {"image_0", "image_1"}) {
    for (const char* f : {"000000.png", "000001.png", "000002.png"}) {
      EXPECT_TRUE(same_bytes(out / "a/sequences/00" / cam / f, out / "b/sequences/00" / cam / f))
          << cam << "/" << f;
    }
  }
  // Rendering again into the same folder replaces the sequence.
  o.seed = 12;
  render_kitti_sequence(o);
  EXPECT_FALSE(
      same_bytes(out / "a/sequences/00/image_0/000000.png", out / "b/sequences/00/image_0/000000.png"));
  for (const auto& entry : fs::directory_iterator(out / "b" / "sequences"))
    EXPECT_EQ(entry.path().filename(), "00");
}

TEST_F(RenderSequence, Kitti00PosesReadBack) {
  GLMBSLAM_REQUIRE_DATA(poses_file, "kitti_odometry/poses/00.txt");
  const PoseList poses = io::read_kitti_poses(poses_file.string());
  ASSERT_EQ(poses.size(), 4541U);
  const fs::path out = test::fresh_temp_dir("render");
  // A short range with images, read back through the KITTI reader.
  SequenceRenderOptions o;
  o.out_dir = out.string();
  o.poses_path = poses_file.string();
  o.frames = "1000:1004";
  render_kitti_sequence(o);
  const auto dataset = io::open_stereo_dataset((out / "sequences" / "00").string());
  ASSERT_EQ(dataset->size(), 4U);
  expect_same_poses(*dataset->ground_truth(),
                    relative_to_first_exact(PoseList(poses.begin() + 1000, poses.begin() + 1004)), 1e-7);
  // The whole sequence as a dry run (no images): 4541 poses and timestamps, equal to the input.
  o.frames = "";
  o.images = false;
  o.sequence = "00dry";
  render_kitti_sequence(o);
  const PoseList written = io::read_kitti_poses((out / "poses" / "00dry.txt").string());
  // Written with 9 significant digits; translations reach ~600 m.
  expect_same_poses(written, relative_to_first_exact(poses), 1e-6);
  // The first pose is the identity, so re-expressing relative to it (as readers do) changes nothing.
  EXPECT_LT((written.front().matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff(), 1e-9);
  expect_same_poses(io::relative_to_first(written), written, 1e-6);
  const std::vector<double> times =
      io::read_kitti_times((out / "sequences" / "00dry" / "times.txt").string());
  ASSERT_EQ(times.size(), 4541U);
  EXPECT_NEAR(times.back(), 454.0, 1e-9);
}

TEST_F(RenderSequence, BadInputIsAClearErrorAndLeavesNoSequence) {
  const fs::path out = test::fresh_temp_dir("render");
  SequenceRenderOptions o;
  o.out_dir = (out / "o").string();
  o.frames = "0:2";
  // Malformed pose line.
  const fs::path bad = out / "bad.txt";
  {
    std::ofstream f(bad);
    f << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n";
  }
  o.poses_path = bad.string();
  try {
    render_kitti_sequence(o);
    ADD_FAILURE() << "malformed poses accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt:2"), std::string::npos) << e.what();
  }
  // Frame range outside the file.
  o.poses_path = "";
  o.frames = "0:100000";
  EXPECT_THROW(render_kitti_sequence(o), InputError);
  o.frames = "5:5";
  EXPECT_THROW(render_kitti_sequence(o), InputError);
  o.frames = "x:3";
  EXPECT_THROW(render_kitti_sequence(o), ConfigError);
  // Unknown calibration name.
  o.frames = "0:2";
  o.calibration = "kitti99";
  EXPECT_THROW(render_kitti_sequence(o), ConfigError);
  o.calibration = "kitti00-02";
  EXPECT_FALSE(fs::exists(out / "o" / "sequences" / "00"));
  // Unwritable output folder (below a regular file).
  o.out_dir = (bad / "sub").string();
  EXPECT_THROW(render_kitti_sequence(o), InputError);
  // Bad sequence name.
  o.out_dir = (out / "o").string();
  o.sequence = "../00";
  EXPECT_THROW(render_kitti_sequence(o), ConfigError);
  EXPECT_FALSE(fs::exists(out / "o" / "sequences" / "00"));
}

TEST_F(RenderSequence, NamedCalibrations) {
  const StereoCalibration c03 = named_kitti_calibration("kitti03");
  EXPECT_EQ(c03.width, 1242);
  EXPECT_EQ(c03.height, 375);
  EXPECT_NEAR(c03.fx * c03.baseline, 387.5744, 1e-9);
  const StereoCalibration c04 = named_kitti_calibration("kitti04-12");
  EXPECT_EQ(c04.width, 1226);
  EXPECT_EQ(c04.height, 370);
  EXPECT_NEAR(c04.cx, 601.8873, 1e-9);
  EXPECT_THROW(named_kitti_calibration("kitti"), ConfigError);
  // A calib.txt file with an explicit size.
  const fs::path out = test::fresh_temp_dir("render");
  write_kitti_calibration(out / "calib.txt", c03);
  const StereoCalibration back = resolve_calibration((out / "calib.txt").string(), "640x200");
  EXPECT_NEAR(back.fx, c03.fx, 1e-9);
  EXPECT_NEAR(back.baseline, c03.baseline, 1e-12);
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.height, 200);
  EXPECT_THROW(resolve_calibration((out / "calib.txt").string(), "640by200"), ConfigError);
  EXPECT_THROW(resolve_calibration((out / "missing.txt").string()), InputError);
  const StereoCalibration euroc = named_kitti_calibration("euroc");
  EXPECT_EQ(euroc.width, 752);
  EXPECT_EQ(euroc.height, 480);
  EXPECT_NEAR(euroc.baseline, 0.110, 1e-12);
}

// Duplicated frames repeat the previous frame byte for byte (images and pose) on the regular clock; dropped
// frames leave gaps in times.txt and the poses.
TEST_F(RenderSequence, DuplicatedAndDroppedFrames) {
  const fs::path out = test::fresh_temp_dir("render_dup");
  SequenceRenderOptions o;
  o.out_dir = (out / "dup").string();
  o.frames = "0:7";
  o.duplicate_every = 3;
  o.calibration = "euroc";
  o.frame_rate = 20.0;
  const PoseList trajectory = default_trajectory(20.0);
  render_kitti_sequence(o);
  const fs::path seq = out / "dup" / "sequences" / "00";
  io::KittiOdometryDataset dup(seq.string());
  ASSERT_EQ(dup.size(), 7u);
  EXPECT_NEAR(dup.timestamps()[6], 0.30, 1e-9);
  for (const char* cam : {"image_0", "image_1"}) {
    EXPECT_TRUE(same_bytes(seq / cam / "000003.png", seq / cam / "000002.png"));
    EXPECT_TRUE(same_bytes(seq / cam / "000006.png", seq / cam / "000005.png"));
    EXPECT_FALSE(same_bytes(seq / cam / "000004.png", seq / cam / "000003.png"));
  }
  const PoseList dup_poses = *dup.ground_truth();
  EXPECT_TRUE(dup_poses[3].isApprox(dup_poses[2], 1e-12));
  EXPECT_FALSE(dup_poses[4].isApprox(dup_poses[3], 1e-6));

  o.out_dir = (out / "drop").string();
  o.duplicate_every = 0;
  o.drop_every = 3;
  render_kitti_sequence(o);
  io::KittiOdometryDataset drop((out / "drop" / "sequences" / "00").string());
  ASSERT_EQ(drop.size(), 5u);  // frames 0 1 3 4 6 of 0..6
  EXPECT_NEAR(drop.timestamps()[2], 0.15, 1e-9);
  EXPECT_NEAR(drop.timestamps()[4], 0.30, 1e-9);
  const PoseList expected =
      relative_to_first_exact({trajectory[0], trajectory[1], trajectory[3], trajectory[4], trajectory[6]});
  expect_same_poses(*drop.ground_truth(), expected, 1e-6);
}

}  // namespace
}  // namespace glmbslam::sim
