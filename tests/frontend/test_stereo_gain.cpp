// The right camera's contrast estimate and the contrast-levelled pyramid levels (frontend/stereo_gain.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <opencv2/core.hpp>

#include "frontend/stereo_gain.hpp"

namespace glmbslam::frontend {
namespace {

// A textured left image and its right view: shifted by `disparity` columns, times `gain`, plus `offset`.
void textured_pair(double gain, double offset, int disparity, cv::Mat& left, cv::Mat& right) {
  cv::RNG rng(3);
  cv::Mat texture(240, 320, CV_8U);
  rng.fill(texture, cv::RNG::UNIFORM, 40, 180);  // × 1.4 stays below 255
  left = texture;
  right = cv::Mat(texture.size(), CV_8U, cv::Scalar(128));
  texture.colRange(disparity, texture.cols)
      .convertTo(right.colRange(0, texture.cols - disparity), -1, gain, offset);
}

std::vector<PatchPair> grid_pairs(int disparity) {
  std::vector<PatchPair> pairs;
  for (int y = 20; y < 220; y += 10)
    for (int x = 40; x < 300; x += 10) pairs.push_back({0, x, y, x - disparity});
  return pairs;
}

TEST(StereoGain, EstimatesTheContrastRatioWhateverTheOffset) {
  for (const double gain : {0.6, 0.9, 1.0, 1.3}) {
    cv::Mat left, right;
    textured_pair(gain, gain > 1.0 ? -30.0 : 25.0, 12, left, right);
    const double g = estimate_right_gain({left}, {right}, grid_pairs(12), 5);
    EXPECT_NEAR(g, 1.0 / gain, 0.01 / gain) << "gain " << gain;  // rounding to grey levels only
  }
}

TEST(StereoGain, FlatOrTooFewPatchesGiveNoEstimate) {
  const cv::Mat flat(240, 320, CV_8U, cv::Scalar(90));
  EXPECT_TRUE(std::isnan(estimate_right_gain({flat}, {flat}, grid_pairs(12), 5)));
  cv::Mat left, right;
  textured_pair(0.8, 0.0, 12, left, right);
  std::vector<PatchPair> few = grid_pairs(12);
  few.resize(10);
  EXPECT_TRUE(std::isnan(estimate_right_gain({left}, {right}, few, 5)));
  // patches that leave the image are skipped, not read out of bounds
  std::vector<PatchPair> outside(40, PatchPair{0, 2, 2, 1});
  EXPECT_TRUE(std::isnan(estimate_right_gain({left}, {right}, outside, 5)));
}

// The levelled images have the same contrast: the image with more is scaled down about mid-grey, nothing
// saturates, and a gain of 1 hands back the inputs.
TEST(StereoGain, LevelsTheHigherContrastImageDown) {
  for (const double gain : {0.7, 1.4}) {
    cv::Mat left, right;
    textured_pair(gain, 0.0, 0, left, right);
    const std::vector<cv::Mat> L = {left}, R = {right};
    ContrastMatchedLevels levels(L, R, 1.0 / gain);
    const cv::Mat &l = levels.left(0), &r = levels.right(0);
    cv::Scalar ml, sl, mr, sr;
    cv::meanStdDev(l, ml, sl);
    cv::meanStdDev(r, mr, sr);
    EXPECT_NEAR(sl[0] / sr[0], 1.0, 0.01) << "gain " << gain;
    double lo = 0.0, hi = 0.0;
    cv::minMaxLoc(gain > 1.0 ? r : l, &lo, &hi);
    EXPECT_GT(lo, 0.0);
    EXPECT_LT(hi, 255.0);
    // the lower-contrast image is the input itself
    EXPECT_EQ((gain > 1.0 ? l : r).data, (gain > 1.0 ? left : right).data);
  }
  cv::Mat left, right;
  textured_pair(1.0, 0.0, 0, left, right);
  const std::vector<cv::Mat> L = {left}, R = {right};
  ContrastMatchedLevels same(L, R, 1.0);
  EXPECT_EQ(same.left(0).data, left.data);
  EXPECT_EQ(same.right(0).data, right.data);
}

}  // namespace
}  // namespace glmbslam::frontend
