// The keypoint noise estimate: known noise in, σ out — on χ² samples directly (with outliers), and through
// the visual odometry on synthetic frames with Gaussian keypoint noise of known σ (the pose fitted to the
// same residuals, wrong matches mixed in).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/random.hpp"
#include "frontend/pixel_noise_estimator.hpp"
#include "frontend/visual_odometry.hpp"
#include "synthetic_stereo.hpp"

namespace glmbslam::frontend {
namespace {

using test::kKittiCamera;

double chi2_3(RandomStream& rng) {
  const double a = rng.normal(), b = rng.normal(), c = rng.normal();
  return a * a + b * b + c * c;
}

// Gaussian residuals, s_i = σ² χ²₃, with 1 % gross outliers (wrong matches far outside): σ comes back within
// the sampling error of 20 000 samples.
TEST(PixelNoiseEstimator, ScaleOfGaussianResidualsWithGrossOutliers) {
  RandomStream rng(3);
  for (const double sigma : {0.3, 0.7, 1.5}) {
    std::vector<double> s;
    for (int i = 0; i < 20000; ++i) {
      if (rng.uniform() < 0.01) {
        s.push_back(sigma * sigma * rng.uniform(1000.0, 10000.0));
      } else {
        s.push_back(sigma * sigma * chi2_3(rng));
      }
    }
    EXPECT_NEAR(std::sqrt(coverage_chi2_3_scale(s, 0.95)), sigma, 0.02 * sigma) << "sigma " << sigma;
  }
  EXPECT_TRUE(std::isnan(coverage_chi2_3_scale({}, 0.95)));
  EXPECT_NEAR(chi2_3_quantile(0.5), 2.365974, 1e-6);
  EXPECT_NEAR(chi2_3_quantile(0.95), 7.814728, 1e-6);
}

// Residuals with shoulders (80 % at σ = 0.4 px, 20 % at 1.2 px): the estimate is the σ whose Gaussian holds
// 95 % of them (checked by counting), wider than the core's 0.4 px.
TEST(PixelNoiseEstimator, ScaleCoversTheResidualsShoulders) {
  RandomStream rng(4);
  std::vector<double> s;
  for (int i = 0; i < 20000; ++i) s.push_back((rng.uniform() < 0.8 ? 0.16 : 1.44) * chi2_3(rng));
  const double sigma2 = coverage_chi2_3_scale(s, 0.95);
  int inside = 0;
  for (double x : s) inside += x <= sigma2 * chi2_3_quantile(0.95);
  EXPECT_NEAR(inside / 20000.0, 0.95, 0.001);
  EXPECT_GT(std::sqrt(sigma2), 0.8);
}

// The window, the clamp, the initial value and the still-camera rule of the online estimator.
TEST(PixelNoiseEstimator, WindowClampAndStillFrames) {
  RandomStream rng(5);
  PixelNoiseOptions o;
  o.initial = 1.0;
  o.floor = 0.3;
  o.ceiling = 2.0;
  o.window_frames = 5;
  o.min_samples = 150;
  o.coverage = 0.95;
  PixelNoiseEstimator e(o);
  auto frame = [&](double sigma, int n) {
    std::vector<double> s;
    for (int i = 0; i < n; ++i) s.push_back(sigma * sigma * chi2_3(rng));
    return s;
  };
  EXPECT_DOUBLE_EQ(e.sigma(), 1.0);
  EXPECT_TRUE(e.add_frame(frame(0.5, 100), 100000, 10.0));
  EXPECT_DOUBLE_EQ(e.sigma(), 1.0);                          // 100 < 150 samples: still the initial value
  EXPECT_FALSE(e.add_frame(frame(0.05, 400), 100000, 0.5));  // a still frame is not used
  EXPECT_TRUE(std::isnan(e.raw_sigma()));
  EXPECT_FALSE(e.estimated());
  for (int k = 0; k < 5; ++k) e.add_frame(frame(0.5, 400), 100000, 10.0);
  EXPECT_NEAR(e.sigma(), 0.5, 0.03);
  EXPECT_TRUE(e.estimated());
  for (int k = 0; k < 5; ++k) e.add_frame(frame(0.1, 400), 100000, 10.0);  // the window forgets the 0.5
  EXPECT_NEAR(e.raw_sigma(), 0.1, 0.006);
  EXPECT_DOUBLE_EQ(e.sigma(), 0.3);  // floor
  for (int k = 0; k < 5; ++k) e.add_frame(frame(3.0, 400), 100000, 10.0);
  EXPECT_DOUBLE_EQ(e.sigma(), 2.0);  // ceiling
  // the pose fitted to D residual dimensions absorbs 6: samples of a 30-dimensional fit are scaled by 30/24
  PixelNoiseEstimator small(o);
  for (int k = 0; k < 5; ++k) {
    std::vector<double> s = frame(0.5, 400);
    for (double& x : s) x *= 24.0 / 30.0;
    small.add_frame(s, 30, 10.0);
  }
  EXPECT_NEAR(small.raw_sigma(), 0.5, 0.03);
}

// Through the VO: synthetic frames with Gaussian noise σ on u_L, v, u_R (all level 0), the measurements'
// configured σ 1 px. The estimate after 20 frames is within 5 % of the true σ (the residuals are those of the
// pose fitted to them; the points the refinement's χ² gate rejects are included, so the distribution is not
// truncated).
TEST(PixelNoiseEstimator, VisualOdometryRecoversTheKeypointNoise) {
  for (const double sigma : {0.4, 1.0}) {
    RandomStream rng(11);
    const test::SyntheticWorld world = test::make_world(3000, rng);
    PixelNoiseOptions o;
    o.floor = 0.01;
    o.ceiling = 10.0;
    StereoVisualOdometry vo(kKittiCamera, VoConfig{}, test::pyramid_scales(), o);
    Pose3 T_wc = Pose3::Identity();
    Pose3 step = Pose3::Identity();
    step.translation() = Eigen::Vector3d(0.05, 0.0, 1.2);
    step.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()).toRotationMatrix();
    auto frame = [&] {
      StereoFrameFeatures f = test::make_frame(world, T_wc, sigma, 0.0, rng);
      for (auto& m : f.measurements) m.pixel_sigma = 1.0;  // the configured σ, not the true one
      return f;
    };
    vo.track(frame());
    VoEstimate e;
    for (int k = 1; k <= 20; ++k) {
      T_wc = T_wc * step;
      e = vo.track(frame());
      ASSERT_EQ(e.status, VoStatus::kTracked) << "frame " << k;
    }
    EXPECT_NEAR(e.pixel_sigma, sigma, 0.05 * sigma) << "sigma " << sigma;
    EXPECT_GT(vo.pixel_noise().samples(), 1000u);
  }
}

// A camera standing still: the frames are not used (a corner seen at the same pixels repeats its error), the
// estimate stays at its initial value.
TEST(PixelNoiseEstimator, StillCameraKeepsTheInitialValue) {
  RandomStream rng(2);
  const test::SyntheticWorld world = test::make_world(3000, rng);
  StereoVisualOdometry vo(kKittiCamera, VoConfig{}, test::pyramid_scales());
  for (int k = 0; k < 10; ++k) {
    const VoEstimate e = vo.track(test::make_frame(world, Pose3::Identity(), 0.5, 0.0, rng));
    EXPECT_DOUBLE_EQ(e.pixel_sigma, 1.0) << "frame " << k;
  }
  EXPECT_EQ(vo.pixel_noise().samples(), 0u);
}

}  // namespace
}  // namespace glmbslam::frontend
