// The stereo matcher's disparities against the renderer's exact depth. A disparity bias δ shortens or
// stretches the whole trajectory by about 2δ/d (d the typical disparity), so the sub-pixel estimator must be
// unbiased on frames where the truth is exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "frontend/stereo_frontend.hpp"
#include "sim/default_trajectory.hpp"
#include "sim/kitti_sequence_writer.hpp"
#include "sim/stereo_procedural_world.hpp"
#include "sim/stereo_renderer.hpp"

namespace glmbslam::frontend {
namespace {

struct ErrorStats {
  std::size_t matches = 0;
  double median = 0.0;     ///< median of measured − true disparity, pixels at level 0
  double mad = 0.0;        ///< median absolute deviation from it
  double mean_gain = 0.0;  ///< mean over the frames of the matcher's σ_L / σ_R
};

double median_of(std::vector<double> x) {
  const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
  std::nth_element(x.begin(), mid, x.end());
  return *mid;
}

/// Measured minus true disparity (f·b / z of the rendered depth at the keypoint) of every stereo match whose
/// 3×3 depth neighbourhood is smooth (no object border), over 12 frames of the default loop.
ErrorStats disparity_errors(const std::string& subpixel_cost, bool photometric_noise,
                            const std::string& subpixel_refine = "fit", double right_gain = 1.0,
                            bool compensate = true) {
  const PoseList trajectory = sim::default_trajectory();
  sim::ProceduralWorldOptions wopt;
  wopt.seed = 5;
  const sim::ProceduralWorld world(trajectory, wopt);
  const StereoCalibration calib = sim::named_kitti_calibration("kitti04-12");
  sim::RenderOptions ropt;
  if (!photometric_noise) ropt.photometric = sim::PhotometricOptions{0.0, 0.0, 0.0};
  sim::StereoRenderer renderer(world, calib, ropt);
  FrontendConfig config;
  config.stereo.subpixel_cost = subpixel_cost;
  config.stereo.subpixel_refine = subpixel_refine;
  config.stereo.gain_compensation = compensate;
  const StereoFrontend frontend(calib, config);
  const double fb = calib.fx * calib.baseline;
  std::vector<double> errors, gains;
  sim::RenderedFrame frame;
  for (int k = 0; k < 12; ++k) {
    const int idx = 7 * k;
    renderer.render(trajectory[static_cast<std::size_t>(idx)], 0.1 * idx, static_cast<std::uint64_t>(idx),
                    frame);
    cv::Mat right = frame.right;  // the right camera's gain: a copy of the rendered image scaled
    if (right_gain != 1.0) frame.right.convertTo(right = cv::Mat(), -1, right_gain, 0.0);
    const auto ff = frontend.process(frame.left, right);
    gains.push_back(ff.stats.right_gain);
    for (const StereoMeasurement& m : ff.measurements) {
      const int u = static_cast<int>(std::lround(m.z(0))), v = static_cast<int>(std::lround(m.z(1)));
      if (u < 1 || v < 1 || u >= frame.depth.cols - 1 || v >= frame.depth.rows - 1) continue;
      float zmin = 1e9f, zmax = 0.0f;
      for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
          zmin = std::min(zmin, frame.depth.at<float>(v + dv, u + du));
          zmax = std::max(zmax, frame.depth.at<float>(v + dv, u + du));
        }
      if (zmin <= 0.0f || zmax > 1.01f * zmin) continue;
      errors.push_back((m.z(0) - m.z(2)) - fb / frame.depth.at<float>(v, u));
    }
  }
  ErrorStats s;
  s.matches = errors.size();
  for (double g : gains) s.mean_gain += g / static_cast<double>(gains.size());
  if (errors.empty()) return s;
  s.median = median_of(errors);
  std::vector<double> deviation;
  for (double e : errors) deviation.push_back(std::abs(e - s.median));
  s.mad = median_of(deviation);
  std::printf(
      "right gain %.2f (estimated %.4f) %-9s %-3s photometric noise %d: %zu matches, disparity error median "
      "%+.4f px, MAD %.4f px\n",
      right_gain, s.mean_gain, subpixel_cost.c_str(), subpixel_refine.c_str(), photometric_noise ? 1 : 0,
      s.matches, s.median, s.mad);
  return s;
}

// stereo.subpixel_refine lk from the centre cost's fit: unbiased and as sharp as the zero-mean cost (measured
// +0.002 / +0.003 px, MAD 0.081 / 0.092 px without / with photometric noise, against the fit's +0.027 /
// +0.030 px and 0.36 / 0.40 px).
TEST(StereoDisparityBias, LucasKanadeRefinementIsUnbiasedAndSharperThanTheFit) {
  for (const bool noise : {false, true}) {
    const ErrorStats fit = disparity_errors("centre", noise);
    const ErrorStats lk = disparity_errors("centre", noise, "lk");
    ASSERT_GT(lk.matches, 5000u);
    EXPECT_LT(std::abs(lk.median), 0.01);
    EXPECT_LT(lk.mad, 0.5 * fit.mad);
  }
}

// A right camera with 0.7 of the left's contrast (independent gains): uncompensated, the centre fit's bias
// grows from +0.027 to +0.076 px (measured, no photometric noise), which stretches the trajectory by ~0.4 %
// at KITTI's disparities; levelling the contrast first restores it (measured +0.030 px), and the estimated
// σ_L / σ_R is 1/0.7 to 0.3 % (measured 1.4294–1.4319 against 1.4286).
TEST(StereoDisparityBias, GainCompensationRemovesTheContrastBias) {
  const ErrorStats same = disparity_errors("centre", false, "fit", 1.0, true);
  const ErrorStats raw = disparity_errors("centre", false, "fit", 0.7, false);
  const ErrorStats levelled = disparity_errors("centre", false, "fit", 0.7, true);
  ASSERT_GT(levelled.matches, 5000u);
  EXPECT_GT(raw.median - same.median, 0.03);
  EXPECT_LT(std::abs(levelled.median - same.median), 0.01);
  EXPECT_LT(levelled.mad, 1.1 * same.mad);
  EXPECT_NEAR(levelled.mean_gain, 1.0 / 0.7, 0.005);
}

TEST(StereoDisparityBias, ZeroMeanCostIsUnbiasedAndSharperThanTheCentreCost) {
  for (const bool noise : {false, true}) {
    const ErrorStats centre = disparity_errors("centre", noise);
    const ErrorStats zero_mean = disparity_errors("zero_mean", noise);
    ASSERT_GT(centre.matches, 5000u);
    ASSERT_GT(zero_mean.matches, 5000u);
    // zero_mean: bias under 0.01 px (measured: +0.004 / +0.006 px), MAD under half the centre cost's
    // (measured 0.08–0.09 px against 0.36–0.40 px); the centre cost's own bias is +0.03 px (printed).
    EXPECT_LT(std::abs(zero_mean.median), 0.01);
    EXPECT_LT(zero_mean.mad, 0.5 * centre.mad);
    EXPECT_GE(zero_mean.matches, centre.matches);
  }
}

}  // namespace
}  // namespace glmbslam::frontend
