// The row-alignment check of a stereo pair against renders whose right image is moved by a known amount:
// none (the renderer's pairs are aligned), a vertical shift, and a small rotation (a roll: an offset growing
// from the left to the right edge).
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "frontend/rectification_check.hpp"
#include "io/stereo_dataset.hpp"
#include "sim/default_trajectory.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "sim/stereo_procedural_world.hpp"
#include "sim/stereo_renderer.hpp"
#include "support/test_data.hpp"

namespace glmbslam::frontend {
namespace {

/// The summary over 6 rendered frames of the default loop whose right image is warped by `right_warp`
/// (2×3, destination from source as cv::warpAffine; empty: unchanged).
RectificationSummary check_rendered(const cv::Mat& right_warp) {
  const PoseList trajectory = sim::default_trajectory();
  sim::ProceduralWorldOptions wopt;
  wopt.seed = 5;
  const sim::ProceduralWorld world(trajectory, wopt);
  const StereoCalibration calib = sim::named_kitti_calibration("kitti04-12");
  sim::StereoRenderer renderer(world, calib, {});
  const StereoFrontend frontend(calib, FrontendConfig{});
  RectificationCheckOptions options;
  options.every_frames = 1;
  RectificationCheck check(options);
  sim::RenderedFrame frame;
  for (int k = 0; k < 6; ++k) {
    renderer.render(trajectory[static_cast<std::size_t>(11 * k)], 0.0, static_cast<std::uint64_t>(k), frame,
                    false);
    cv::Mat right = frame.right;
    if (!right_warp.empty())
      cv::warpAffine(frame.right, right, right_warp, frame.right.size(), cv::INTER_LINEAR);
    check.add_frame(static_cast<std::size_t>(k), frontend.process(frame.left, right));
  }
  const RectificationSummary s = check.summary();
  std::printf("median %+.3f px, field %+.3f %+.3f %+.3f %+.3f px, corners up to %.3f px (%zu samples)\n",
              s.median_px, s.field[0], s.field[1], s.field[2], s.field[3], s.corner_max_px, s.samples);
  return s;
}

TEST(RectificationCheck, AlignedRenderedPairsShowNoOffset) {
  const RectificationSummary s = check_rendered(cv::Mat());
  ASSERT_TRUE(s.valid());
  EXPECT_EQ(s.frames, 6u);
  EXPECT_LT(std::abs(s.median_px), 0.02);
  EXPECT_LT(s.corner_max_px, 0.1);
}

TEST(RectificationCheck, MeasuresAVerticalShiftOfTheRightImage) {
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 0, 0, 1, 0.5);  // content 0.5 px lower
  const RectificationSummary s = check_rendered(shift);
  ASSERT_TRUE(s.valid());
  EXPECT_NEAR(s.median_px, 0.5, 0.03);
  EXPECT_NEAR(s.field[0], 0.5, 0.05);
  EXPECT_NEAR(s.corner_max_px, 0.5, 0.1);
}

TEST(RectificationCheck, MeasuresARollAsTheFieldsXTerm) {
  // rotated by 0.05° about the image centre: v moves by about θ·(u − c_u), ±0.54 px at the left and right
  // edges
  const StereoCalibration calib = sim::named_kitti_calibration("kitti04-12");
  const double theta_deg = 0.05;
  const cv::Mat roll = cv::getRotationMatrix2D(
      cv::Point2f(static_cast<float>(calib.width / 2.0), static_cast<float>(calib.height / 2.0)), -theta_deg,
      1.0);
  const RectificationSummary s = check_rendered(roll);
  ASSERT_TRUE(s.valid());
  const double edge = theta_deg * M_PI / 180.0 * calib.width / 2.0;  // v change at x = ±1
  EXPECT_NEAR(s.field[1], edge, 0.1 * edge);
  EXPECT_LT(std::abs(s.field[0]), 0.05);
  EXPECT_LT(std::abs(s.field[2]), 0.1);
}

// KITTI raw 2011_09_26_drive_0001 (the stored drive): its rectified pair is not row-aligned, mostly an xy
// term (measured with every 10th frame: median −0.26 px, field −0.38 + 0.07x + 0.03y + 1.30xy px, corners
// up to 1.72 px).
TEST(RectificationCheck, KittiRawDrive0001IsNotRowAligned) {
  const auto drive = test::shared_data_dir() / "kitti_raw" / "2011_09_26" / "2011_09_26_drive_0001_sync";
  if (!std::filesystem::exists(drive)) GTEST_SKIP() << "KITTI raw drive not found at " << drive;
  const auto dataset = io::open_stereo_dataset(drive.string());
  const StereoFrontend frontend(dataset->calibration(), FrontendConfig{});
  RectificationCheck check;
  for (std::size_t k = 0; k < dataset->size(); k += 10) {
    const io::StereoFrame frame = dataset->load(k);
    check.add_frame(k, frontend.process(frame.left, frame.right));
  }
  const RectificationSummary s = check.summary();
  ASSERT_TRUE(s.valid());
  EXPECT_LT(s.median_px, -0.15);
  EXPECT_GT(s.field[3], 0.8);
  EXPECT_GT(s.corner_max_px, 1.0);
}

}  // namespace
}  // namespace glmbslam::frontend
