#pragma once
// Synthetic stereo frames for the VO tests: world points with fixed random descriptors, projected into a
// KITTI-like rectified stereo camera with Gaussian pixel noise, optionally with displaced (outlier)
// keypoints.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "core/random.hpp"
#include "frontend/stereo_frontend.hpp"
#include "frontend/stereo_projection.hpp"

namespace glmbslam::frontend::test {

inline const StereoCamera kKittiCamera(721.5377, 721.5377, 609.5593, 172.854, 0.5371506);
constexpr int kWidth = 1241;
constexpr int kHeight = 376;

inline std::vector<double> pyramid_scales() {
  std::vector<double> s(8, 1.0);
  for (int l = 1; l < 8; ++l) s[l] = s[l - 1] * 1.2;
  return s;
}

struct SyntheticWorld {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<std::uint8_t, 32>> descriptors;
};

/// `n` points in a corridor ahead of the camera path (x ∈ [−15, 15], y ∈ [−3, 2], z ∈ [3, 120]).
inline SyntheticWorld make_world(int n, RandomStream& rng) {
  SyntheticWorld w;
  for (int i = 0; i < n; ++i) {
    w.points.emplace_back(rng.uniform(-15, 15), rng.uniform(-3, 2), rng.uniform(3, 120));
    std::array<std::uint8_t, 32> d;
    for (auto& b : d) b = static_cast<std::uint8_t>(rng.index(256));
    w.descriptors.push_back(d);
  }
  return w;
}

/// The pyramid level at which an extractor finds a point at `depth` whose image is one pixel wide at 30 m:
/// level 0 from 30 m on, one level (×1.2) coarser for every 1.2 times closer, at most level 7.
inline int octave_at_depth(double depth) {
  return static_cast<int>(std::clamp(std::lround(std::log(30.0 / depth) / std::log(1.2)), 0L, 7L));
}

/// The frame seen from T_wc: every visible point (depth 2–70 m, inside the image) becomes a left keypoint and
/// a stereo measurement with noise σ on u_L, v, u_R. A fraction `outliers` of the keypoints is displaced by
/// 4–12 px (their descriptors still match, so they become wrong correspondences). Keypoints are at pyramid
/// level 0, or with `octave_by_depth` at octave_at_depth (a point's level changes as the camera approaches).
inline StereoFrameFeatures make_frame(const SyntheticWorld& w, const Pose3& T_wc, double sigma,
                                      double outliers, RandomStream& rng, bool octave_by_depth = false) {
  StereoFrameFeatures f;
  const StereoCamera& cam = kKittiCamera;
  std::vector<cv::Mat> rows;
  for (std::size_t i = 0; i < w.points.size(); ++i) {
    const Eigen::Vector3d p = T_wc.inverse() * w.points[i];
    if (p.z() < 2.0 || p.z() > 70.0) continue;
    Eigen::Vector3d z = cam.project(p);
    if (z.x() < 20 || z.z() < 20 || z.x() > kWidth - 20 || z.y() < 20 || z.y() > kHeight - 20) continue;
    for (int k = 0; k < 3; ++k) z(k) += rng.normal(0.0, sigma);
    if (rng.uniform() < outliers) {
      const double a = rng.uniform(0, 2 * M_PI), r = rng.uniform(4, 12);
      z.x() += r * std::cos(a);
      z.z() += r * std::cos(a);
      z.y() += r * std::sin(a);
    }
    const int octave = octave_by_depth ? octave_at_depth(p.z()) : 0;
    cv::KeyPoint kp(static_cast<float>(z.x()), static_cast<float>(z.y()), 31.0f, 0.0f, 50.0f, octave);
    f.left.keypoints.push_back(kp);
    rows.push_back(cv::Mat(1, 32, CV_8U, const_cast<std::uint8_t*>(w.descriptors[i].data())).clone());
    StereoMeasurement m;
    m.z = z;
    m.pixel_sigma = sigma;
    m.point = cam.triangulate(z);
    m.point_covariance = cam.triangulation_covariance(z, sigma);
    std::copy(w.descriptors[i].begin(), w.descriptors[i].end(), m.descriptor.begin());
    m.octave = octave;
    m.left_index = static_cast<int>(f.left.keypoints.size()) - 1;
    f.left_to_measurement.push_back(static_cast<int>(f.measurements.size()));
    f.measurements.push_back(m);
  }
  if (!rows.empty()) cv::vconcat(rows, f.left.descriptors);
  cv::RNG image_rng(static_cast<std::uint64_t>(rng.index(1u << 30)));  // filler content, seeded from rng
  cv::Mat image(kHeight, kWidth, CV_8U);
  image_rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  cv::Mat thumb(kHeight / 4, kWidth / 4, CV_8U);
  image_rng.fill(thumb, cv::RNG::UNIFORM, 0, 256);
  f.left.pyramid = {image, thumb};
  return f;
}

}  // namespace glmbslam::frontend::test
