// ground_truth.txt (app/ground_truth_output.hpp): written exactly when every frame has a measured pose, and
// no stale file left behind when the ground truth is partial.
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "app/ground_truth_output.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::app {
namespace {

namespace fs = std::filesystem;

PoseList three_poses() {
  PoseList poses(3, Pose3::Identity());
  poses[1].translation() << 0.25, -0.5, 1.0;
  poses[2].linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()).toRotationMatrix();
  poses[2].translation() << 0.5, -1.0, 2.125;
  return poses;
}

class GroundTruthOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("glmbslam_test_gt_output_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(GroundTruthOutput, EveryFrameMeasuredWritesThePosesInKittiFormat) {
  const PoseList gt = three_poses();
  ASSERT_TRUE(write_ground_truth_file(dir_, &gt, {}));
  ASSERT_TRUE(write_ground_truth_file(dir_, &gt, {1, 1, 1}));
  const PoseList read = io::read_kitti_poses((dir_ / "ground_truth.txt").string());
  ASSERT_EQ(read.size(), gt.size());
  for (std::size_t i = 0; i < gt.size(); ++i) EXPECT_TRUE(read[i].isApprox(gt[i], 1e-8)) << i;
}

TEST_F(GroundTruthOutput, PartialGroundTruthWritesNothingAndRemovesAnEarlierFile) {
  const PoseList gt = three_poses();
  ASSERT_TRUE(write_ground_truth_file(dir_, &gt, {}));  // an earlier run into the same folder
  ASSERT_TRUE(fs::exists(dir_ / "ground_truth.txt"));
  EXPECT_FALSE(write_ground_truth_file(dir_, &gt, {1, 0, 1}));  // frame 1 holds a placeholder
  EXPECT_FALSE(fs::exists(dir_ / "ground_truth.txt"));
}

TEST_F(GroundTruthOutput, NoGroundTruthWritesNothingAndRemovesAnEarlierFile) {
  const PoseList gt = three_poses();
  ASSERT_TRUE(write_ground_truth_file(dir_, &gt, {}));
  EXPECT_FALSE(write_ground_truth_file(dir_, nullptr, {}));
  EXPECT_FALSE(fs::exists(dir_ / "ground_truth.txt"));
}

}  // namespace
}  // namespace glmbslam::app
