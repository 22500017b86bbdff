#include "io/kitti_odometry.hpp"

#include <gtest/gtest.h>

#include "io/trajectory_io.hpp"
#include "support/test_data.hpp"
#include "tests/io/fake_kitti.hpp"

namespace glmbslam::io {
namespace {

using test::expect_input_error;
using test::make_fake_kitti_sequence;
using test::write_image;
using test::write_text;
namespace fs = std::filesystem;

TEST(KittiOdometry, ReadsSynthesisedSequence) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 5);
  KittiOdometryDataset ds(seq.string());
  EXPECT_EQ(ds.size(), 5u);
  EXPECT_EQ(ds.name(), "kitti odometry 07");
  const auto& c = ds.calibration();
  EXPECT_DOUBLE_EQ(c.fx, 700.0);
  EXPECT_DOUBLE_EQ(c.fy, 710.0);
  EXPECT_DOUBLE_EQ(c.cx, 20.0);
  EXPECT_DOUBLE_EQ(c.cy, 15.0);
  EXPECT_DOUBLE_EQ(c.baseline, 0.5);  // −P1[0,3]/fx = 350/700
  EXPECT_EQ(c.width, test::kFakeWidth);
  EXPECT_EQ(c.height, test::kFakeHeight);
  ASSERT_EQ(ds.timestamps().size(), 5u);
  EXPECT_NEAR(ds.timestamps()[3], 0.3, 1e-9);
  ASSERT_TRUE(ds.ground_truth().has_value());
  ASSERT_EQ(ds.ground_truth()->size(), 5u);
  EXPECT_NEAR((*ds.ground_truth())[4].translation().z(), 4.0, 1e-12);
  EXPECT_EQ(fs::path(ds.ground_truth_path()), root / "poses" / "07.txt");
  const StereoFrame f = ds.load(3);
  EXPECT_EQ(f.index, 3u);
  EXPECT_NEAR(f.timestamp, 0.3, 1e-9);
  ASSERT_EQ(f.left.type(), CV_8UC1);
  ASSERT_EQ(f.right.type(), CV_8UC1);
  EXPECT_EQ(f.left.at<std::uint8_t>(0, 0), 3);
  EXPECT_EQ(f.right.at<std::uint8_t>(0, 0), 103);
  EXPECT_EQ(f.left.cols, test::kFakeWidth);
  EXPECT_THROW(ds.load(5), InputError);
}

TEST(KittiOdometry, GroundTruthIsOptionalAndCanBeGivenExplicitly) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 3, /*with_poses=*/false);
  KittiOdometryDataset without(seq.string());
  EXPECT_FALSE(without.ground_truth().has_value());
  write_text(root / "elsewhere.txt",
             "1 0 0 1 0 1 0 0 0 0 1 0\n1 0 0 2 0 1 0 0 0 0 1 0\n1 0 0 3 0 1 0 0 0 0 1 0\n");
  KittiOdometryDataset with(seq.string(), (root / "elsewhere.txt").string());
  ASSERT_TRUE(with.ground_truth().has_value());
  // Relative to frame 0.
  EXPECT_NEAR((*with.ground_truth())[0].translation().norm(), 0.0, 1e-12);
  EXPECT_NEAR((*with.ground_truth())[2].translation().x(), 2.0, 1e-12);
  expect_input_error([&] { KittiOdometryDataset(seq.string(), (root / "missing.txt").string()); },
                     "missing.txt", "cannot open");
}

TEST(KittiOdometry, TrailingSlashFindsGroundTruth) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 2);
  KittiOdometryDataset ds(seq.string() + "/");
  EXPECT_TRUE(ds.ground_truth().has_value());
  EXPECT_EQ(ds.name(), "kitti odometry 07");
}

TEST(KittiOdometry, MissingFolder) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  expect_input_error([&] { KittiOdometryDataset((root / "nope").string()); }, "nope", "not found");
  const auto seq = make_fake_kitti_sequence(root, 2);
  fs::remove_all(seq / "image_1");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "image_1", "not found");
}

TEST(KittiOdometry, LeftRightCountMismatch) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 3);
  fs::remove(seq / "image_1" / "000001.png");
  // the message names the image without a partner, not only the counts
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, (seq / "image_0" / "000001.png").string(),
                     "left image has no partner " + (seq / "image_1" / "000001.png").string() +
                         " (image_0 has 3 images, image_1 has 2)");
  fs::copy_file(seq / "image_1" / "000000.png", seq / "image_1" / "000001.png");
  fs::copy_file(seq / "image_1" / "000000.png", seq / "image_1" / "000003.png");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, (seq / "image_1" / "000003.png").string(),
                     "right image has no partner");
}

TEST(KittiOdometry, LeftRightNamesMismatch) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 3);
  fs::rename(seq / "image_1" / "000002.png", seq / "image_1" / "000009.png");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "image_0/000002.png", "has no partner");
}

TEST(KittiOdometry, TimesCountMismatch) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 3);
  write_text(seq / "times.txt", "0\n0.1\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "times.txt", "2 timestamps");
}

TEST(KittiOdometry, TimesNotIncreasingOrNotFinite) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 3);
  write_text(seq / "times.txt", "0\n0.2\n0.2\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "times.txt:3", "not strictly increasing");
  write_text(seq / "times.txt", "0\nnan\n0.2\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "times.txt:2", "not finite");
  write_text(seq / "times.txt", "0\n0.1 0.2\n0.3\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "times.txt:2", "exactly one number");
  fs::remove(seq / "times.txt");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "times.txt", "not found");
}

TEST(KittiOdometry, CalibLineWithWrongNumberOfValues) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 2);
  write_text(seq / "calib.txt",
             "P0: 7.0e+02 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "P1: 7.0e+02 0 2.0e+01 -3.5e+02 0 7.1e+02 1.5e+01 0 0 0 1\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "calib.txt:2",
                     "has 11 values, expected 12");
  write_text(seq / "calib.txt",
             "P0: 7.0e+02 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "P1: 7.0e+02 0 2.0e+01 -3.5e+02 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "Tr: 1 0 0 0 0 1 0 0 0 0 1 0 5\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "calib.txt:3",
                     "has 13 values, expected 12");
}

TEST(KittiOdometry, CalibNonFiniteMissingBadBaselineOrOfOtherImages) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 2);
  write_text(seq / "calib.txt",
             "P0: inf 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "P1: 7.0e+02 0 2.0e+01 -3.5e+02 0 7.1e+02 1.5e+01 0 0 0 1 0\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "calib.txt:1", "non-finite");
  write_text(seq / "calib.txt", "P0: 7.0e+02 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "calib.txt", "'P1' is missing");
  write_text(seq / "calib.txt",
             "P0: 7.0e+02 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "P1: 7.0e+02 0 2.0e+01 3.5e+02 0 7.1e+02 1.5e+01 0 0 0 1 0\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "calib.txt", "must be negative");
  write_text(seq / "calib.txt",
             "P0: 7.0e+02 0 2.0e+01 0 0 7.1e+02 1.5e+01 0 0 0 1 0\n"
             "P1: 7.0e+02 0 2.0e+01 -3.5e+02 0 7.1e+02 1.5e+01 0 0 x 1 0\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "calib.txt:2", "not a number");
  // A KITTI 00-02 calibration (cx 607, cy 185) next to the small fake images: the principal point lies
  // outside.
  write_text(seq / "calib.txt",
             "P0: 7.188560e+02 0 6.071928e+02 0 0 7.188560e+02 1.852157e+02 0 0 0 1 0\n"
             "P1: 7.188560e+02 0 6.071928e+02 -3.861448e+02 0 7.188560e+02 1.852157e+02 0 0 0 1 0\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "calib.txt",
                     "the calibration does not belong to these images");
  fs::remove(seq / "calib.txt");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "calib.txt", "not found");
}

TEST(KittiOdometry, MissingOrUnreadableImage) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 3);
  KittiOdometryDataset ds(seq.string());
  fs::remove(seq / "image_0" / "000001.png");
  expect_input_error([&] { ds.load(1); }, "000001.png", "missing");
  write_text(seq / "image_1" / "000002.png", "this is not a png");
  expect_input_error([&] { ds.load(2); }, "000002.png", "unreadable");
  // Unreadable first image at open time.
  const auto root2 = test::fresh_temp_dir("kitti_odo2");
  const auto seq2 = make_fake_kitti_sequence(root2, 2);
  write_text(seq2 / "image_0" / "000000.png", "garbage");
  expect_input_error([&] { KittiOdometryDataset(seq2.string()); }, "000000.png", "unreadable");
  // Empty image folders.
  fs::remove(seq2 / "image_0" / "000000.png");
  fs::remove(seq2 / "image_0" / "000001.png");
  expect_input_error([&] { KittiOdometryDataset(seq2.string()); }, "image_0", "no .png");
}

TEST(KittiOdometry, ImageSizeCheckedOnLoad) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 3);
  write_image(seq / "image_1" / "000002.png", test::kFakeWidth + 2, test::kFakeHeight, 7);
  KittiOdometryDataset ds(seq.string());
  EXPECT_NO_THROW(ds.load(1));
  expect_input_error([&] { ds.load(2); }, "000002.png", "expected 40x30");
}

// 16-bit PNGs (machine-vision cameras store 10- or 12-bit data in them) are scaled by the bit depth their
// values use; OpenCV's own 8-bit conversion keeps the high byte and would leave a 12-bit image at 0–15.
TEST(KittiOdometry, SixteenBitImagesAreScaledByTheirBitDepth) {
  const auto root = test::fresh_temp_dir("kitti_odo_16");
  const auto seq = make_fake_kitti_sequence(root, 3);
  const auto write16 = [&](const fs::path& file, int max_value) {
    cv::Mat img(test::kFakeHeight, test::kFakeWidth, CV_16UC1);
    for (int r = 0; r < img.rows; ++r)
      for (int c = 0; c < img.cols; ++c)
        img.at<std::uint16_t>(r, c) =
            static_cast<std::uint16_t>((r * img.cols + c) * max_value / (img.total() - 1));
    ASSERT_TRUE(cv::imwrite(file.string(), img)) << file;
  };
  write16(seq / "image_0" / "000001.png", 4095);   // 12-bit data
  write16(seq / "image_1" / "000001.png", 65535);  // the full 16 bits
  write16(seq / "image_0" / "000002.png", 200);    // 8-bit data in a 16-bit file: unchanged
  KittiOdometryDataset ds(seq.string());
  const StereoFrame f = ds.load(1);
  ASSERT_EQ(f.left.type(), CV_8UC1);
  ASSERT_EQ(f.right.type(), CV_8UC1);
  double lo = 0.0, hi = 0.0;
  cv::minMaxLoc(f.left, &lo, &hi);
  EXPECT_EQ(lo, 0.0);
  EXPECT_EQ(hi, 255.0);
  cv::minMaxLoc(f.right, &lo, &hi);
  EXPECT_EQ(hi, 255.0);
  // the middle of the 12-bit ramp lands in the middle of the 8-bit range
  const int mid = static_cast<int>(f.left.total() / 2);
  EXPECT_NEAR(f.left.at<std::uint8_t>(mid / f.left.cols, mid % f.left.cols), 127.5, 1.0);
  cv::minMaxLoc(ds.load(2).left, &lo, &hi);
  EXPECT_EQ(hi, 200.0);
}

TEST(KittiOdometry, EachSideLoadsAloneAsInThePair) {
  const auto root = test::fresh_temp_dir("kitti_odo_side");
  const auto seq = make_fake_kitti_sequence(root, 3);
  KittiOdometryDataset ds(seq.string());
  const StereoFrame frame = ds.load(1);
  EXPECT_EQ(cv::norm(ds.load_image(1, StereoSide::kLeft), frame.left, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(ds.load_image(1, StereoSide::kRight), frame.right, cv::NORM_INF), 0.0);
  EXPECT_EQ(frame.timestamp, ds.timestamps()[1]);
  expect_input_error([&] { ds.load_image(3, StereoSide::kRight); }, "kitti odometry", "out of range");
  expect_input_error([&] { ds.load(3); }, "kitti odometry", "out of range");
  // an unreadable right image is the right side's error only
  write_text(seq / "image_1" / "000002.png", "this is not a png");
  EXPECT_NO_THROW(ds.load_image(2, StereoSide::kLeft));
  expect_input_error([&] { ds.load_image(2, StereoSide::kRight); }, "000002.png", "unreadable");
}

TEST(KittiOdometry, GroundTruthProblems) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 3);
  write_text(root / "poses" / "07.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "07.txt",
                     "has 2 poses but the sequence has 3");
  write_text(root / "poses" / "07.txt",
             "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n1 0 0 0 0 1 0 0 0 0 1 2\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "07.txt:2", "has 11 numbers, expected 12");
  write_text(root / "poses" / "07.txt",
             "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 nan\n1 0 0 0 0 1 0 0 0 0 1 2\n");
  expect_input_error([&] { KittiOdometryDataset(seq.string()); }, "07.txt:2", "non-finite");
}

TEST(KittiOdometry, CalibrationOfSequence00Format) {
  // The real KITTI calib.txt of sequences 00-02 (values from the KITTI odometry development kit).
  const auto root = test::fresh_temp_dir("kitti_odo");
  write_text(
      root / "calib.txt",
      "P0: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 0.000000000000e+00 0.000000000000e+00 "
      "7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 0.000000000000e+00 0.000000000000e+00 "
      "1.000000000000e+00 0.000000000000e+00\n"
      "P1: 7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 -3.861448000000e+02 "
      "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 0.000000000000e+00 "
      "0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\n");
  const StereoCalibration c = read_kitti_odometry_calibration((root / "calib.txt").string());
  EXPECT_DOUBLE_EQ(c.fx, 718.856);
  EXPECT_DOUBLE_EQ(c.cx, 607.1928);
  EXPECT_DOUBLE_EQ(c.cy, 185.2157);
  EXPECT_NEAR(c.baseline * c.fx, 386.1448, 1e-9);  // data README: baseline·fx = 386.1448
}

TEST(KittiOdometry, FindGroundTruthStandardLayout) {
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root, 1);
  EXPECT_EQ(fs::path(find_kitti_ground_truth(seq.string())), root / "poses" / "07.txt");
  fs::remove(root / "poses" / "07.txt");
  EXPECT_EQ(find_kitti_ground_truth(seq.string()), "");
}

TEST(KittiOdometry, FindGroundTruthThroughASymbolicLink) {
  // a link to sequences/07 from elsewhere (named otherwise) still finds poses/07.txt beside the real folder
  const auto root = test::fresh_temp_dir("kitti_odo");
  const auto seq = make_fake_kitti_sequence(root / "kitti", 1);
  fs::create_directory_symlink(seq, root / "my_drive");
  const fs::path expected = root / "kitti" / "poses" / "07.txt";
  for (const std::string link : {"my_drive", "my_drive/"}) {
    const std::string found = find_kitti_ground_truth((root / link).string());
    ASSERT_FALSE(found.empty()) << link;
    EXPECT_TRUE(fs::equivalent(found, expected)) << found;
  }
  EXPECT_EQ(find_kitti_ground_truth((root / "missing").string()), "");
}

TEST(KittiOdometry, RealPoses00Has4541Poses) {
  GLMBSLAM_REQUIRE_DATA(poses, "kitti_odometry/poses/00.txt");
  const PoseList p = read_kitti_poses(poses.string());
  ASSERT_EQ(p.size(), 4541u);
  EXPECT_LT((p.front().matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff(), 1e-6);
  double length = 0.0;
  for (std::size_t i = 1; i < p.size(); ++i) length += (p[i].translation() - p[i - 1].translation()).norm();
  EXPECT_NEAR(length, 3724.0, 10.0);  // sequence 00 is ~3.7 km (data README)
}

}  // namespace
}  // namespace glmbslam::io
