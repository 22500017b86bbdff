#include "io/kitti_raw.hpp"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "io/oxts.hpp"
#include "support/test_data.hpp"
#include "tests/io/fake_kitti.hpp"

namespace glmbslam::io {
namespace {

using test::expect_input_error;
using test::ten_digits;
using test::write_image;
using test::write_text;
namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

/// A fake date folder with the three calibration files (identity extrinsics except where stated) and a drive
/// with `frames` frames (oxts included when `with_oxts`). Returns the drive folder.
fs::path make_fake_raw_drive(const fs::path& root, int frames, bool with_oxts = true) {
  const fs::path date = root / "2011_09_26";
  const fs::path drive = date / "2011_09_26_drive_0042_sync";
  write_text(date / "calib_cam_to_cam.txt",
             "calib_time: 09-Jan-2012 13:57:47\n"
             "corner_dist: 9.950000e-02\n"
             "R_rect_00: 1 0 0 0 1 0 0 0 1\n"
             "P_rect_00: 7.0e+02 0 2.0e+01 0 0 7.0e+02 1.5e+01 0 0 0 1 0\n"
             "P_rect_01: 7.0e+02 0 2.0e+01 -3.5e+02 0 7.0e+02 1.5e+01 0 0 0 1 0\n");
  // Velodyne ← IMU: identity. Camera ← velodyne: the usual axis permutation (x right = −y_velo, y down =
  // −z_velo, z forward = x_velo).
  write_text(date / "calib_imu_to_velo.txt", "calib_time: x\nR: 1 0 0 0 1 0 0 0 1\nT: 0 0 0\n");
  write_text(date / "calib_velo_to_cam.txt", "calib_time: x\nR: 0 -1 0 0 0 -1 1 0 0\nT: 0 0 0\n");
  std::string stamps;
  for (int i = 0; i < frames; ++i) {
    write_image(drive / "image_00" / "data" / (ten_digits(i) + ".png"), test::kFakeWidth, test::kFakeHeight,
                i);
    write_image(drive / "image_01" / "data" / (ten_digits(i) + ".png"), test::kFakeWidth, test::kFakeHeight,
                50 + i);
    char buf[64];
    std::snprintf(buf, sizeof buf, "2011-09-26 13:02:25.%09d\n", 100000000 * i);
    stamps += buf;
    if (with_oxts) {
      // Heading east (yaw 0), moving 1 m a frame east along the equator-relative Mercator x axis.
      const double lat = 49.0;
      const double lon = 8.4 + i * 180.0 / (kPi * 6378137.0 * std::cos(lat * kPi / 180.0));
      std::string line;
      std::snprintf(buf, sizeof buf, "%.12f %.12f 100 0 0 0", lat, lon);
      line = buf;
      for (int k = 6; k < 30; ++k) line += " 0";
      write_text(drive / "oxts" / "data" / (ten_digits(i) + ".txt"), line + "\n");
    }
  }
  write_text(drive / "image_00" / "timestamps.txt", stamps);
  write_text(drive / "image_01" / "timestamps.txt", stamps);
  return drive;
}

TEST(KittiRaw, ReadsSynthesisedDrive) {
  const auto root = test::fresh_temp_dir("kitti_raw");
  const auto drive = make_fake_raw_drive(root, 4);
  KittiRawDataset ds(drive.string());
  EXPECT_EQ(ds.size(), 4u);
  EXPECT_EQ(ds.name(), "kitti raw 2011_09_26_drive_0042_sync");
  EXPECT_DOUBLE_EQ(ds.calibration().fx, 700.0);
  EXPECT_DOUBLE_EQ(ds.calibration().baseline, 0.5);
  EXPECT_EQ(ds.calibration().width, test::kFakeWidth);
  ASSERT_EQ(ds.timestamps().size(), 4u);
  EXPECT_NEAR(ds.timestamps()[0], 0.0, 1e-12);
  EXPECT_NEAR(ds.timestamps()[3], 0.3, 1e-9);
  const StereoFrame f = ds.load(2);
  EXPECT_EQ(f.left.at<std::uint8_t>(0, 0), 2);
  EXPECT_EQ(f.right.at<std::uint8_t>(0, 0), 52);
  // Driving 1 m a frame east with the IMU x axis east (yaw 0): the camera z axis is the IMU x axis, so camera
  // poses move along +z.
  ASSERT_TRUE(ds.ground_truth().has_value());
  const PoseList& gt = *ds.ground_truth();
  ASSERT_EQ(gt.size(), 4u);
  EXPECT_TRUE(gt[0].isApprox(Pose3::Identity(), 1e-12));
  EXPECT_NEAR(gt[3].translation().x(), 0.0, 1e-6);
  EXPECT_NEAR(gt[3].translation().y(), 0.0, 1e-6);
  EXPECT_NEAR(gt[3].translation().z(), 3.0, 1e-6);
}

TEST(KittiRaw, TimestampsParsing) {
  const auto root = test::fresh_temp_dir("kitti_raw");
  const auto f = root / "timestamps.txt";
  // Across midnight and a month boundary.
  write_text(f, "2011-09-30 23:59:59.900000000\n2011-10-01 00:00:00.150000000\n");
  const auto t = read_kitti_raw_timestamps(f.string());
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t[1], 0.25, 1e-9);
  write_text(f, "2011-09-26 13:02:25.1\n2011-09-26 13:02:25.1\n");
  expect_input_error([&] { read_kitti_raw_timestamps(f.string()); }, "timestamps.txt:2",
                     "not strictly increasing");
  write_text(f, "2011-09-26 13:02:25.1\n2011/09/26 13:02:26.1\n");
  expect_input_error([&] { read_kitti_raw_timestamps(f.string()); }, "timestamps.txt:2", "YYYY-MM-DD");
  write_text(f, "2011-09-26 13:02:25.1x\n");
  expect_input_error([&] { read_kitti_raw_timestamps(f.string()); }, "timestamps.txt:1", "YYYY-MM-DD");
  write_text(f, "\n");
  expect_input_error([&] { read_kitti_raw_timestamps(f.string()); }, "timestamps.txt", "empty");
}

TEST(KittiRaw, BadInput) {
  const auto root = test::fresh_temp_dir("kitti_raw");
  expect_input_error([&] { KittiRawDataset((root / "none").string()); }, "none", "not found");
  const auto drive = make_fake_raw_drive(root, 3);
  const auto date = drive.parent_path();
  {
    fs::remove(drive / "image_01" / "data" / (ten_digits(1) + ".png"));
    expect_input_error([&] { KittiRawDataset(drive.string()); }, ten_digits(1) + ".png",
                       "left image has no partner");
    write_image(drive / "image_01" / "data" / (ten_digits(1) + ".png"), test::kFakeWidth, test::kFakeHeight,
                1);
  }
  {
    write_text(drive / "image_00" / "timestamps.txt", "2011-09-26 13:02:25.1\n");
    expect_input_error([&] { KittiRawDataset(drive.string()); }, "timestamps.txt", "1 timestamps");
    write_text(drive / "image_00" / "timestamps.txt",
               "2011-09-26 13:02:25.1\n2011-09-26 13:02:25.2\n2011-09-26 13:02:25.3\n");
  }
  EXPECT_NO_THROW(KittiRawDataset(drive.string()));
  {
    write_text(date / "calib_cam_to_cam.txt",
               "R_rect_00: 1 0 0 0 1 0 0 0 1\nP_rect_00: 7 0 2 0 0 7 1 0 0 0 1\n");
    expect_input_error([&] { KittiRawDataset(drive.string()); }, "calib_cam_to_cam.txt:2",
                       "has 11 values, expected 12");
    write_text(date / "calib_cam_to_cam.txt",
               "R_rect_00: 1 0 0 0 1 0 0 0 2\nP_rect_00: 7 0 2 0 0 7 1 0 0 0 1 0\nP_rect_01: 7 0 2 -3 0 7 1 "
               "0 0 0 1 0\n");
    expect_input_error([&] { KittiRawDataset(drive.string()); }, "calib_cam_to_cam.txt", "not a rotation");
    write_text(date / "calib_cam_to_cam.txt",
               "R_rect_00: 1 0 0 0 1 0 0 0 1\nP_rect_00: 7 0 2 0 0 7 1 0 0 0 1 0\nP_rect_01: 7 0 2 -3 0 7 1 "
               "0 0 0 1 0\n");
    EXPECT_NO_THROW(KittiRawDataset(drive.string()));
  }
  {
    write_text(date / "calib_velo_to_cam.txt", "R: 0 -1 0 0 0 -1 1 0 0\nT: 0 0\n");
    expect_input_error([&] { KittiRawDataset(drive.string()); }, "calib_velo_to_cam.txt:2", "has 2 values");
    write_text(date / "calib_velo_to_cam.txt", "R: 0 -1 0 0 0 -1 1 0 0\nT: 0 nan 0\n");
    expect_input_error([&] { KittiRawDataset(drive.string()); }, "calib_velo_to_cam.txt:2", "non-finite");
    fs::remove(date / "calib_velo_to_cam.txt");
    expect_input_error([&] { KittiRawDataset(drive.string()); }, "calib_velo_to_cam.txt", "not found");
    write_text(date / "calib_velo_to_cam.txt", "R: 0 -1 0 0 0 -1 1 0 0\nT: 0 0 0\n");
  }
  {
    // A broken or missing oxts record leaves its frame without ground truth; the drive still opens.
    const auto rec = drive / "oxts" / "data" / (ten_digits(2) + ".txt");
    const std::vector<char> first_two{1, 1, 0};
    write_text(rec, "49 8.4 100 0 0 0\n");
    EXPECT_EQ(KittiRawDataset(drive.string()).ground_truth_mask(), first_two);
    std::string line = "49 8.4 inf";
    for (int k = 3; k < 30; ++k) line += " 0";
    write_text(rec, line + "\n");
    EXPECT_EQ(KittiRawDataset(drive.string()).ground_truth_mask(), first_two);
    fs::remove(rec);
    const KittiRawDataset partial(drive.string());
    ASSERT_TRUE(partial.ground_truth().has_value());
    EXPECT_EQ(partial.ground_truth().value().size(), 3u);
    EXPECT_EQ(partial.ground_truth_mask(), first_two);
    // the placeholder of frame 2 is the nearest measured pose
    EXPECT_TRUE(partial.ground_truth().value()[2].isApprox(partial.ground_truth().value()[1]));
  }
  {
    // An explicit ground-truth file replaces oxts.
    write_text(root / "gt.txt",
               "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n1 0 0 0 0 1 0 0 0 0 1 2\n");
    KittiRawDataset ds(drive.string(), (root / "gt.txt").string());
    ASSERT_TRUE(ds.ground_truth().has_value());
    EXPECT_NEAR((*ds.ground_truth())[2].translation().z(), 2.0, 1e-12);
    fs::remove_all(drive / "oxts");
    KittiRawDataset no_gt(drive.string());
    EXPECT_FALSE(no_gt.ground_truth().has_value());
  }
  {
    write_text(drive / "image_00" / "data" / (ten_digits(1) + ".png"), "not an image");
    KittiRawDataset ds(drive.string());
    expect_input_error([&] { ds.load(1); }, ten_digits(1) + ".png", "unreadable");
  }
}

TEST(Oxts, DevkitConventionOnHandComputedRecords) {
  // Two records: the second 0.001° further north and 0.002° further east, 2 m higher, yaw 90°.
  OxtsRecord a;
  a.lat = 49.0;
  a.lon = 8.0;
  a.alt = 100.0;
  OxtsRecord b = a;
  b.lat += 0.001;
  b.lon += 0.002;
  b.alt += 2.0;
  b.yaw = kPi / 2;
  b.roll = 0.1;
  const PoseList p = oxts_to_imu_poses({a, b});
  ASSERT_EQ(p.size(), 2u);
  const double s = std::cos(49.0 * kPi / 180.0);
  const double er = 6378137.0;
  const double dx = s * er * 0.002 * kPi / 180.0;
  const double dy =
      s * er *
      (std::log(std::tan((90.0 + 49.001) * kPi / 360.0)) - std::log(std::tan((90.0 + 49.0) * kPi / 360.0)));
  EXPECT_NEAR(p[1].translation().x(), dx, 1e-6);
  EXPECT_NEAR(p[1].translation().y(), dy, 1e-6);
  EXPECT_NEAR(p[1].translation().z(), 2.0, 1e-9);
  // R = Rz(yaw)·Ry(pitch)·Rx(roll): the IMU x axis points north (world +y), its y axis is rolled about x.
  const Eigen::Matrix3d R = p[1].linear();
  EXPECT_NEAR(R(1, 0), 1.0, 1e-12);
  EXPECT_NEAR(R(0, 1), -std::cos(0.1), 1e-12);
  EXPECT_NEAR(R(2, 1), std::sin(0.1), 1e-12);
}

TEST(Oxts, CameraPosesAreConjugated) {
  Pose3 T_cam_imu = Pose3::Identity();
  T_cam_imu.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T_cam_imu.translation() = Eigen::Vector3d(0.5, -1.0, 2.0);
  Pose3 motion = Pose3::Identity();
  motion.linear() = Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  motion.translation() = Eigen::Vector3d(3.0, 1.0, 0.0);
  const PoseList cam = imu_to_camera_poses({Pose3::Identity(), motion}, T_cam_imu);
  EXPECT_TRUE(cam[0].isApprox(Pose3::Identity(), 1e-12));
  // A point fixed in the world seen from IMU frame 1 must equal what the camera pose predicts.
  const Eigen::Vector3d p_imu1(1.0, 2.0, 3.0);
  const Eigen::Vector3d p_imu0 = motion * p_imu1;
  const Eigen::Vector3d expected_cam0 = T_cam_imu * p_imu0;
  const Eigen::Vector3d predicted_cam0 = cam[1] * (T_cam_imu * p_imu1);
  EXPECT_LT((expected_cam0 - predicted_cam0).norm(), 1e-12);
}

TEST(KittiRaw, RealDrive0001Acceptance) {
  GLMBSLAM_REQUIRE_DATA(drive, "kitti_raw/2011_09_26/2011_09_26_drive_0001_sync");
  KittiRawDataset ds(drive.string());
  ASSERT_EQ(ds.size(), 108u);
  const StereoCalibration& c = ds.calibration();
  EXPECT_NEAR(c.fx, 721.5377, 1e-9);
  EXPECT_NEAR(c.fy, 721.5377, 1e-9);
  EXPECT_NEAR(c.cx, 609.5593, 1e-9);
  EXPECT_NEAR(c.cy, 172.854, 1e-9);
  EXPECT_NEAR(c.baseline, 387.5744 / 721.5377, 1e-9);
  EXPECT_EQ(c.width, 1242);
  EXPECT_EQ(c.height, 375);
  ASSERT_EQ(ds.timestamps().size(), 108u);
  EXPECT_NEAR(ds.timestamps().back(), 11.0, 0.2);  // ~10 Hz
  ASSERT_TRUE(ds.ground_truth().has_value());
  const PoseList& gt = *ds.ground_truth();
  ASSERT_EQ(gt.size(), 108u);
  EXPECT_TRUE(gt.front().isApprox(Pose3::Identity(), 1e-12));
  double length = 0.0;
  for (std::size_t i = 1; i < gt.size(); ++i)
    length += (gt[i].translation() - gt[i - 1].translation()).norm();
  EXPECT_NEAR(length, 106.9, 0.1);
  const Eigen::Vector3d last = gt.back().translation();
  std::printf("kitti raw 0001 ground truth: %zu poses, path length %.4f m, final (%.4f, %.4f, %.4f) m\n",
              gt.size(), length, last.x(), last.y(), last.z());
  EXPECT_NEAR(last.x(), 10.30, 0.05);
  EXPECT_NEAR(last.y(), -0.40, 0.05);
  EXPECT_NEAR(last.z(), 106.30, 0.05);
  const StereoFrame f = ds.load(107);
  EXPECT_EQ(f.left.cols, 1242);
  EXPECT_EQ(f.right.rows, 375);
  EXPECT_EQ(f.left.type(), CV_8UC1);
}

}  // namespace
}  // namespace glmbslam::io
