// ORB extraction and stereo matching: bad inputs never crash; on a real KITTI pair the features are spread
// over the image and the stereo matches obey the rectified-row and depth-range constraints.
#include <cmath>
#include <utility>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.hpp"
#include "frontend/stereo_frontend.hpp"
#include "support/test_data.hpp"

namespace glmbslam::frontend {
namespace {

StereoCalibration kitti_raw_calibration() {
  StereoCalibration c;
  c.fx = c.fy = 721.5377;
  c.cx = 609.5593;
  c.cy = 172.854;
  c.baseline = 387.5744 / 721.5377;
  c.width = 1242;
  c.height = 375;
  return c;
}

TEST(StereoFrontend, EmptyImagesGiveNoMeasurements) {
  const StereoFrontend fe(kitti_raw_calibration(), FrontendConfig{});
  const StereoFrameFeatures f = fe.process(cv::Mat(), cv::Mat());
  EXPECT_TRUE(f.left.keypoints.empty());
  EXPECT_TRUE(f.measurements.empty());
}

TEST(StereoFrontend, MissingRightImageGivesLeftFeaturesOnly) {
  cv::Mat left(375, 1242, CV_8U);
  cv::RNG rng(7);
  rng.fill(left, cv::RNG::UNIFORM, 0, 256);
  const StereoFrontend fe(kitti_raw_calibration(), FrontendConfig{});
  const StereoFrameFeatures f = fe.process(left, cv::Mat());
  EXPECT_GT(f.left.keypoints.size(), 100u);
  EXPECT_EQ(f.left.descriptors.rows, static_cast<int>(f.left.keypoints.size()));
  EXPECT_TRUE(f.measurements.empty());
}

TEST(StereoFrontend, BlankAndTinyImagesDoNotCrash) {
  const StereoFrontend fe(kitti_raw_calibration(), FrontendConfig{});
  const cv::Mat blank = cv::Mat::zeros(375, 1242, CV_8U);
  EXPECT_TRUE(fe.process(blank, blank).measurements.empty());
  const cv::Mat tiny = cv::Mat::zeros(5, 7, CV_8U);
  EXPECT_TRUE(fe.process(tiny, tiny).left.keypoints.empty());
}

TEST(StereoFrontend, SizeMismatchIsAnInputError) {
  const StereoFrontend fe(kitti_raw_calibration(), FrontendConfig{});
  EXPECT_THROW(fe.process(cv::Mat::zeros(375, 1242, CV_8U), cv::Mat::zeros(370, 1242, CV_8U)), InputError);
}

/// A textured pair: smoothed noise on the left, the right one shifted 12 px (a fronto-parallel plane).
std::pair<cv::Mat, cv::Mat> textured_pair() {
  cv::Mat noise(375, 1242, CV_8U);
  cv::RNG rng(11);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::Mat left;
  cv::GaussianBlur(noise, left, cv::Size(5, 5), 1.2);
  cv::Mat right = cv::Mat::zeros(left.size(), CV_8U);
  left(cv::Rect(12, 0, left.cols - 12, left.rows)).copyTo(right(cv::Rect(0, 0, left.cols - 12, left.rows)));
  return {left, right};
}

TEST(StereoFrontend, LoadersGiveTheFeaturesOfThePair) {
  const auto [left, right] = textured_pair();
  for (const bool parallel : {true, false}) {
    FrontendConfig config;
    config.orb.parallel = parallel;
    const StereoFrontend fe(kitti_raw_calibration(), config);
    const StereoFrameFeatures a = fe.process(left, right);
    const StereoFrameFeatures b = fe.process([&] { return left; }, [&] { return right; });
    ASSERT_GT(a.measurements.size(), 100u) << "parallel " << parallel;
    ASSERT_EQ(a.left.keypoints.size(), b.left.keypoints.size());
    ASSERT_EQ(a.right.keypoints.size(), b.right.keypoints.size());
    ASSERT_EQ(a.measurements.size(), b.measurements.size());
    EXPECT_EQ(cv::norm(a.left.descriptors, b.left.descriptors, cv::NORM_HAMMING), 0.0);
    EXPECT_EQ(cv::norm(a.right.descriptors, b.right.descriptors, cv::NORM_HAMMING), 0.0);
    for (std::size_t m = 0; m < a.measurements.size(); ++m) {
      EXPECT_EQ(a.measurements[m].z, b.measurements[m].z);
      EXPECT_EQ(a.measurements[m].point, b.measurements[m].point);
    }
    EXPECT_EQ(a.left_to_measurement, b.left_to_measurement);
    // a missing side, as process(left, empty)
    const StereoFrameFeatures c = fe.process([&] { return left; }, [] { return cv::Mat(); });
    EXPECT_EQ(c.left.keypoints.size(), a.left.keypoints.size());
    EXPECT_TRUE(c.measurements.empty());
  }
}

TEST(StereoFrontend, LoaderErrorsAndSizeMismatchPropagate) {
  const auto [left, right] = textured_pair();
  const StereoFrontend fe(kitti_raw_calibration(), FrontendConfig{});
  auto failing = []() -> cv::Mat { throw InputError("image_1/000007.png", "cannot be read"); };
  EXPECT_THROW(fe.process([&] { return left; }, failing), InputError);
  EXPECT_THROW(fe.process(failing, [&] { return right; }), InputError);
  EXPECT_THROW(fe.process(failing, failing), InputError);
  const cv::Mat shorter = right(cv::Rect(0, 0, right.cols, right.rows - 5)).clone();
  EXPECT_THROW(fe.process([&] { return left; }, [&] { return shorter; }), InputError);
  // the frontend stays usable after the errors
  EXPECT_GT(fe.process([&] { return left; }, [&] { return right; }).measurements.size(), 100u);
}

TEST(StereoFrontend, RealKittiPairSpreadAndStereoConstraints) {
  GLMBSLAM_REQUIRE_DATA(drive, "kitti_raw/2011_09_26/2011_09_26_drive_0001_sync");
  const cv::Mat left = cv::imread((drive / "image_00/data/0000000050.png").string(), cv::IMREAD_GRAYSCALE);
  const cv::Mat right = cv::imread((drive / "image_01/data/0000000050.png").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(left.empty());
  const FrontendConfig config;
  const StereoFrontend fe(kitti_raw_calibration(), config);
  const StereoFrameFeatures f = fe.process(left, right);
  EXPECT_GE(f.left.keypoints.size(), 1900u);
  EXPECT_LE(f.left.keypoints.size(), 2000u);
  EXPECT_EQ(f.left.descriptors.rows, static_cast<int>(f.left.keypoints.size()));
  // Spread: keypoints in at least 90 % of the cells of a 10 × 4 grid over the image.
  std::vector<int> cells(40, 0);
  for (const auto& k : f.left.keypoints) {
    cells[std::min(3, static_cast<int>(k.pt.y * 4 / left.rows)) * 10 +
          std::min(9, static_cast<int>(k.pt.x * 10 / left.cols))]++;
  }
  int occupied = 0;
  for (int c : cells) occupied += c > 0;
  EXPECT_GE(occupied, 36);
  // Every pyramid level is used.
  std::vector<int> levels(8, 0);
  for (const auto& k : f.left.keypoints) levels[k.octave]++;
  for (int l = 0; l < 8; ++l) EXPECT_GT(levels[l], 0) << "level " << l;

  EXPECT_GE(f.measurements.size(), 400u);
  const double bf = fe.camera().bf();
  for (const StereoMeasurement& m : f.measurements) {
    const double d = m.z.x() - m.z.z();
    EXPECT_GE(d, bf / config.stereo.max_depth_m - 1e-9);
    EXPECT_LE(d, bf / config.stereo.min_depth_m + 1e-9);
    const cv::KeyPoint& kr = f.right.keypoints[static_cast<std::size_t>(m.right_index)];
    EXPECT_LE(std::abs(kr.pt.y - m.z.y()), config.stereo.row_band_px * std::pow(1.2, kr.octave) + 1e-3);
    EXPECT_NEAR(m.point.z(), bf / d, 1e-9);
    EXPECT_EQ(f.left_to_measurement[static_cast<std::size_t>(m.left_index)], &m - f.measurements.data());
    // The propagated depth variance grows with depth: σ_z = z² σ_d / (f b), σ_d = √2 σ_px.
    const double sz = m.point.z() * m.point.z() * std::sqrt(2.0) * m.pixel_sigma / bf;
    EXPECT_NEAR(std::sqrt(m.point_covariance(2, 2)), sz, 1e-6 * sz);
  }
}

}  // namespace
}  // namespace glmbslam::frontend
