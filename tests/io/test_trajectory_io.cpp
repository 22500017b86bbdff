#include "io/trajectory_io.hpp"

#include <cmath>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/lie.hpp"
#include "support/test_data.hpp"
#include "tests/io/fake_kitti.hpp"

namespace glmbslam::io {
namespace {

using test::expect_input_error;
using test::write_text;
namespace fs = std::filesystem;

PoseList sample_poses(std::size_t n) {
  PoseList poses;
  for (std::size_t i = 0; i < n; ++i) {
    Pose3 T = Pose3::Identity();
    const double a = 0.37 * static_cast<double>(i);
    T.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d(0.3, -1.0, 0.2).normalized()).toRotationMatrix();
    T.translation() =
        Eigen::Vector3d(123.456789 * std::sin(a), -7.25 * static_cast<double>(i), 1000.0 + 0.001 * a);
    poses.push_back(T);
  }
  return poses;
}

std::size_t count_lines(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) ++n;
  return n;
}

TEST(TrajectoryIo, KittiRoundTrip) {
  const auto dir = test::fresh_temp_dir("traj");
  const auto file = dir / "poses.txt";
  const PoseList poses = sample_poses(20);
  write_kitti_poses(file.string(), poses);
  EXPECT_EQ(count_lines(file), 20u);  // one line per input frame
  const PoseList back = read_kitti_poses(file.string());
  ASSERT_EQ(back.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    // %.9g: 9 significant digits → relative error ≤ 5e-9 per entry.
    EXPECT_LT((back[i].matrix() - poses[i].matrix()).cwiseAbs().maxCoeff(), 1e-5) << i;
    EXPECT_LT((back[i].linear() - poses[i].linear()).cwiseAbs().maxCoeff(), 1e-8) << i;
  }
  const Trajectory t = read_trajectory(file.string(), TrajectoryFormat::kKitti);
  EXPECT_EQ(t.poses.size(), 20u);
  EXPECT_TRUE(t.timestamps.empty());
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);  // no temporary left
}

TEST(TrajectoryIo, TumRoundTrip) {
  const auto dir = test::fresh_temp_dir("traj");
  const auto file = dir / "traj.tum";
  const PoseList poses = sample_poses(15);
  std::vector<double> stamps;
  for (std::size_t i = 0; i < poses.size(); ++i)
    stamps.push_back(1317384506.40 + 0.1 * static_cast<double>(i));
  write_tum_trajectory(file.string(), poses, stamps);
  EXPECT_EQ(count_lines(file), 15u);
  const Trajectory back = read_tum_trajectory(file.string());
  ASSERT_EQ(back.poses.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_NEAR(back.timestamps[i], stamps[i], 1e-6) << i;
    EXPECT_LT((back.poses[i].translation() - poses[i].translation()).norm(), 1e-5) << i;
    EXPECT_LT(rotation_angle(Eigen::Matrix3d(back.poses[i].linear().transpose() * poses[i].linear())), 1e-7)
        << i;
  }
  EXPECT_EQ(read_trajectory(file.string(), TrajectoryFormat::kTum).poses.size(), 15u);
}

TEST(TrajectoryIo, TumCommentsAndBlankLines) {
  const auto dir = test::fresh_temp_dir("traj");
  const auto file = dir / "t.tum";
  write_text(file,
             "# timestamp tx ty tz qx qy qz qw\n\n  # indented comment\n1.0 1 2 3 0 0 0 1\n2.0 4 5 6 0 0 "
             "0.7071067811865476 0.7071067811865476\n");
  const Trajectory t = read_tum_trajectory(file.string());
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_EQ(t.poses[0].translation(), Eigen::Vector3d(1, 2, 3));
  // qz = qw = 1/√2: 90° about z.
  EXPECT_NEAR(t.poses[1].linear()(1, 0), 1.0, 1e-12);
}

TEST(TrajectoryIo, KittiMalformedLines) {
  const auto dir = test::fresh_temp_dir("traj");
  const auto file = dir / "bad.txt";
  const std::string good = "1 0 0 0 0 1 0 0 0 0 1 0\n";
  write_text(file, good + "1 0 0 0 0 1 0 0 0 0 1\n");
  expect_input_error([&] { read_kitti_poses(file.string()); }, "bad.txt:2", "has 11 numbers, expected 12");
  write_text(file, good + good + "1 0 0 0 0 1 0 0 0 0 1 0 0\n");
  expect_input_error([&] { read_kitti_poses(file.string()); }, "bad.txt:3", "has 13 numbers, expected 12");
  write_text(file, "1 0 0 0 0 1 0 0 0 0 1 abc\n");
  expect_input_error([&] { read_kitti_poses(file.string()); }, "bad.txt:1", "not a number");
  write_text(file, good + "1 0 0 inf 0 1 0 0 0 0 1 0\n");
  expect_input_error([&] { read_kitti_poses(file.string()); }, "bad.txt:2", "non-finite");
  write_text(file, good + "1 0 0 0 0 1 0 0 0 0 1 nan\n");
  expect_input_error([&] { read_kitti_poses(file.string()); }, "bad.txt:2", "non-finite");
  write_text(file, "2 0 0 0 0 1 0 0 0 0 1 0\n");
  expect_input_error([&] { read_kitti_poses(file.string()); }, "bad.txt:1", "not a rotation");
  write_text(file, "-1 0 0 0 0 1 0 0 0 0 1 0\n");  // reflection
  expect_input_error([&] { read_kitti_poses(file.string()); }, "bad.txt:1", "not a rotation");
  // Windows line endings and blank lines are accepted.
  write_text(file, "1 0 0 0 0 1 0 0 0 0 1 0\r\n\r\n1 0 0 0 0 1 0 0 0 0 1 5\r\n");
  EXPECT_EQ(read_kitti_poses(file.string()).size(), 2u);
}

TEST(TrajectoryIo, EmptyAndMissingFiles) {
  const auto dir = test::fresh_temp_dir("traj");
  write_text(dir / "empty.txt", "");
  expect_input_error([&] { read_kitti_poses((dir / "empty.txt").string()); }, "empty.txt", "empty");
  write_text(dir / "blank.txt", "\n  \n");
  expect_input_error([&] { read_kitti_poses((dir / "blank.txt").string()); }, "blank.txt", "empty");
  write_text(dir / "comments.tum", "# only a comment\n");
  expect_input_error([&] { read_tum_trajectory((dir / "comments.tum").string()); }, "comments.tum", "empty");
  expect_input_error([&] { read_kitti_poses((dir / "none.txt").string()); }, "none.txt", "cannot open");
  expect_input_error([&] { read_tum_trajectory((dir / "none.tum").string()); }, "none.tum", "cannot open");
}

TEST(TrajectoryIo, TumMalformedLines) {
  const auto dir = test::fresh_temp_dir("traj");
  const auto file = dir / "bad.tum";
  write_text(file, "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  expect_input_error([&] { read_tum_trajectory(file.string()); }, "bad.tum:2", "has 7 numbers, expected 8");
  write_text(file, "1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  expect_input_error([&] { read_tum_trajectory(file.string()); }, "bad.tum:2", "not strictly increasing");
  write_text(file, "1.0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n");
  expect_input_error([&] { read_tum_trajectory(file.string()); }, "bad.tum:2", "not strictly increasing");
  write_text(file, "1.0 0 nan 0 0 0 0 1\n");
  expect_input_error([&] { read_tum_trajectory(file.string()); }, "bad.tum:1", "non-finite");
  write_text(file, "1.0 0 0 0 0 0 0 2\n");
  expect_input_error([&] { read_tum_trajectory(file.string()); }, "bad.tum:1", "not unit length");
  write_text(file, "1.0 0 0 0 0 0 0 one\n");
  expect_input_error([&] { read_tum_trajectory(file.string()); }, "bad.tum:1", "not a number");
}

TEST(TrajectoryIo, WritersRejectBadInput) {
  const auto dir = test::fresh_temp_dir("traj");
  const PoseList poses = sample_poses(3);
  expect_input_error(
      [&] {
        write_tum_trajectory((dir / "t.tum").string(), poses, {0.0, 1.0});
      },
      "t.tum", "3 poses but 2 timestamps");
  PoseList bad = poses;
  bad[1].translation().y() = std::numeric_limits<double>::quiet_NaN();
  expect_input_error([&] { write_kitti_poses((dir / "k.txt").string(), bad); }, "k.txt", "not finite");
  expect_input_error(
      [&] {
        write_tum_trajectory((dir / "t.tum").string(), bad, {0.0, 1.0, 2.0});
      },
      "t.tum", "not finite");
  expect_input_error(
      [&] {
        write_tum_trajectory((dir / "t.tum").string(), poses, {0.0, 1.0, 1.0});
      },
      "t.tum", "not strictly increasing");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
  expect_input_error([&] { write_kitti_poses((dir / "no_dir" / "k.txt").string(), poses); }, "k.txt",
                     "cannot");
}

TEST(TrajectoryIo, RelativeToFirst) {
  const PoseList poses = sample_poses(5);
  const PoseList rel = relative_to_first(poses);
  ASSERT_EQ(rel.size(), 5u);
  EXPECT_TRUE(rel[0].isApprox(Pose3::Identity(), 1e-12));
  for (std::size_t i = 0; i < 5; ++i) EXPECT_TRUE((poses[0] * rel[i]).isApprox(poses[i], 1e-12)) << i;
  EXPECT_TRUE(relative_to_first({}).empty());
}

TEST(TrajectoryIo, ParseFormat) {
  EXPECT_EQ(parse_trajectory_format("kitti"), TrajectoryFormat::kKitti);
  EXPECT_EQ(parse_trajectory_format("tum"), TrajectoryFormat::kTum);
  EXPECT_THROW(parse_trajectory_format("euroc"), ConfigError);
}

TEST(TrajectoryIo, RealResultsFilesHave4541Poses) {
  GLMBSLAM_REQUIRE_DATA(orb, "kitti_odometry/results/00_orbslam2_stereo.txt");
  EXPECT_EQ(read_kitti_poses(orb.string()).size(), 4541u);
  GLMBSLAM_REQUIRE_DATA(sptam, "kitti_odometry/results/00_sptam.txt");
  EXPECT_EQ(read_kitti_poses(sptam.string()).size(), 4541u);
}

}  // namespace
}  // namespace glmbslam::io
