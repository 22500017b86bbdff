#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/stereo_dataset.hpp"
#include "support/test_data.hpp"
#include "tests/io/fake_kitti.hpp"

namespace glmbslam::io {
namespace {

using test::expect_input_error;
using test::write_image;
using test::write_text;
namespace fs = std::filesystem;

TEST(OpenDataset, DetectsKittiOdometry) {
  const auto root = test::fresh_temp_dir("open_ds");
  const auto seq = test::make_fake_kitti_sequence(root, 2);
  EXPECT_EQ(detect_dataset_format(seq.string()), DatasetFormat::kKittiOdometry);
  const auto ds = open_stereo_dataset(seq.string());
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(ds->size(), 2u);
  EXPECT_EQ(ds->name(), "kitti odometry 07");
  EXPECT_TRUE(ds->ground_truth().has_value());
}

TEST(OpenDataset, GroundTruthOverridePassedThrough) {
  const auto root = test::fresh_temp_dir("open_ds");
  const auto seq = test::make_fake_kitti_sequence(root, 2, /*with_poses=*/false);
  write_text(root / "gt.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 5\n");
  const auto ds = open_stereo_dataset(seq.string(), DatasetFormat::kAuto, (root / "gt.txt").string());
  ASSERT_TRUE(ds->ground_truth().has_value());
  EXPECT_NEAR((*ds->ground_truth())[1].translation().z(), 5.0, 1e-12);
}

TEST(OpenDataset, DetectsKittiRawAndVictoriaPark) {
  const auto root = test::fresh_temp_dir("open_ds");
  fs::create_directories(root / "raw" / "image_00");
  fs::create_directories(root / "raw" / "image_01");
  EXPECT_EQ(detect_dataset_format((root / "raw").string()), DatasetFormat::kKittiRaw);
  write_text(root / "vp" / "aa3_dr.mat", "");
  EXPECT_EQ(detect_dataset_format((root / "vp").string()), DatasetFormat::kVictoriaPark);
  expect_input_error([&] { open_stereo_dataset((root / "vp").string()); }, "vp", "not a stereo dataset");
  expect_input_error([&] { open_stereo_dataset((root / "vp").string(), DatasetFormat::kVictoriaPark); }, "vp",
                     "not a stereo dataset");
}

TEST(OpenDataset, UnknownOrMissing) {
  const auto root = test::fresh_temp_dir("open_ds");
  fs::create_directories(root / "empty");
  expect_input_error([&] { detect_dataset_format((root / "empty").string()); }, "empty",
                     "unknown dataset layout");
  expect_input_error([&] { detect_dataset_format((root / "missing").string()); }, "missing", "not found");
  write_text(root / "file.txt", "x");
  expect_input_error([&] { detect_dataset_format((root / "file.txt").string()); }, "file.txt",
                     "not a folder");
}

TEST(OpenDataset, FormatOverrideIsHonoured) {
  const auto root = test::fresh_temp_dir("open_ds");
  const auto seq = test::make_fake_kitti_sequence(root, 2);
  // Forcing KITTI raw on an odometry folder reads it as a raw drive, which lacks image_00.
  expect_input_error([&] { open_stereo_dataset(seq.string(), DatasetFormat::kKittiRaw); }, "image_00",
                     "not found");
  // Forcing odometry on a folder that auto-detection would call Victoria Park.
  write_text(seq / "aa3_dr.mat", "");
  EXPECT_EQ(open_stereo_dataset(seq.string(), DatasetFormat::kKittiOdometry)->size(), 2u);
}

TEST(OpenDataset, ParseFormatNames) {
  EXPECT_EQ(parse_dataset_format("auto"), DatasetFormat::kAuto);
  EXPECT_EQ(parse_dataset_format("kitti"), DatasetFormat::kKittiOdometry);
  EXPECT_EQ(parse_dataset_format("kitti_raw"), DatasetFormat::kKittiRaw);
  EXPECT_EQ(parse_dataset_format("victoria_park"), DatasetFormat::kVictoriaPark);
  EXPECT_THROW(parse_dataset_format("tum"), ConfigError);
  for (auto f : {DatasetFormat::kAuto, DatasetFormat::kKittiOdometry, DatasetFormat::kKittiRaw,
                 DatasetFormat::kVictoriaPark}) {
    EXPECT_EQ(parse_dataset_format(to_string(f)), f);
  }
}

TEST(OpenDataset, RealDataDetection) {
  GLMBSLAM_REQUIRE_DATA(drive, "kitti_raw/2011_09_26/2011_09_26_drive_0001_sync");
  EXPECT_EQ(detect_dataset_format(drive.string()), DatasetFormat::kKittiRaw);
  const auto ds = open_stereo_dataset(drive.string());
  EXPECT_EQ(ds->size(), 108u);
  GLMBSLAM_REQUIRE_DATA(vp, "victoria_park");
  EXPECT_EQ(detect_dataset_format(vp.string()), DatasetFormat::kVictoriaPark);
}

}  // namespace
}  // namespace glmbslam::io
