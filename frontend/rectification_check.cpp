#include "frontend/rectification_check.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

namespace glmbslam::frontend {

namespace {

/// The field's basis at (x, y): v_off = cᵀ basis(x, y).
Eigen::Vector4d basis(double x, double y) {
  return {1.0, x, y, x * y};
}

}  // namespace

RectificationCheck::RectificationCheck(const RectificationCheckOptions& options) : options_(options) {}

void RectificationCheck::add_frame(std::size_t k, const StereoFrameFeatures& frame) {
  const bool gathering = samples_.size() < static_cast<std::size_t>(options_.min_samples) &&
                         frames_ < static_cast<std::size_t>(options_.max_gathering_frames);
  if (!gathering && k % static_cast<std::size_t>(std::max(1, options_.every_frames)) != 0) return;
  if (frame.left.pyramid.empty() || frame.right.pyramid.empty()) return;
  const cv::Mat& L = frame.left.pyramid[0];
  const cv::Mat& R = frame.right.pyramid[0];
  if (L.empty() || R.empty() || L.size() != R.size()) return;
  const double width = L.cols, height = L.rows;
  std::vector<std::size_t> level0;
  for (std::size_t i = 0; i < frame.measurements.size(); ++i) {
    if (frame.measurements[i].octave == 0) level0.push_back(i);
  }
  if (level0.empty()) return;
  ++frames_;
  const int h = options_.half_window, m = options_.margin;
  const std::size_t stride =
      std::max<std::size_t>(1, level0.size() / static_cast<std::size_t>(options_.max_points));
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 1e-4);
  int tried = 0;
  for (std::size_t s = 0; s < level0.size() && tried < options_.max_points; s += stride, ++tried) {
    const StereoMeasurement& z = frame.measurements[level0[s]];
    const int ul = static_cast<int>(std::lround(z.z(0))), v = static_cast<int>(std::lround(z.z(1)));
    const int ur = static_cast<int>(std::lround(z.z(2)));
    if (ul - h < 0 || ul + h >= L.cols || v - h - m < 0 || v + h + m >= L.rows || ur - h - m < 0 ||
        ur + h + m >= R.cols)
      continue;
    const cv::Mat patch = L(cv::Rect(ul - h, v - h, 2 * h + 1, 2 * h + 1));
    const cv::Mat region = R(cv::Rect(ur - h - m, v - h - m, 2 * h + 1 + 2 * m, 2 * h + 1 + 2 * m));
    // the patch's top-left corner in the region: (m + u_R − round(u_R), m) when the pair is aligned
    cv::Mat warp = (cv::Mat_<float>(2, 3) << 1.0f, 0.0f, static_cast<float>(m + z.z(2) - ur), 0.0f, 1.0f,
                    static_cast<float>(m));
    try {
      cv::findTransformECC(patch, region, warp, cv::MOTION_TRANSLATION, criteria, cv::noArray(), 1);
    } catch (const cv::Exception&) {
      continue;  // no texture to align (the correlation does not converge)
    }
    const double dy = warp.at<float>(1, 2) - m;
    if (!std::isfinite(dy) || std::abs(dy) >= m - 0.5) continue;  // at the margin: not measured
    samples_.push_back({(2.0 * ul - width) / width, (2.0 * v - height) / height, dy});
  }
}

RectificationSummary RectificationCheck::summary() const {
  RectificationSummary out;
  out.samples = samples_.size();
  out.frames = frames_;
  if (samples_.empty()) return out;
  std::vector<double> dy;
  dy.reserve(samples_.size());
  for (const Sample& s : samples_) dy.push_back(s.dy);
  const auto mid = dy.begin() + static_cast<std::ptrdiff_t>(dy.size() / 2);
  std::nth_element(dy.begin(), mid, dy.end());
  out.median_px = *mid;
  if (!out.valid()) return out;
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  Eigen::Vector4d b = Eigen::Vector4d::Zero();
  for (const Sample& s : samples_) {
    const Eigen::Vector4d j = basis(s.x, s.y);
    A += j * j.transpose();
    b += j * s.dy;
  }
  const Eigen::LDLT<Eigen::Matrix4d> ldlt(A);
  const Eigen::Vector4d c = ldlt.solve(b);
  if (!c.allFinite()) return out;
  for (int i = 0; i < 4; ++i) out.field[static_cast<std::size_t>(i)] = c(i);
  double rss = 0.0;  // residual variance → covariance of c: σ² (JᵀJ)⁻¹
  for (const Sample& s : samples_) rss += std::pow(s.dy - basis(s.x, s.y).dot(c), 2);
  const double sigma2 = rss / static_cast<double>(samples_.size() - 4);
  const Eigen::Matrix4d cov = sigma2 * ldlt.solve(Eigen::Matrix4d::Identity());
  for (const double x : {-1.0, 1.0}) {
    for (const double y : {-1.0, 1.0}) {
      const Eigen::Vector4d j = basis(x, y);
      const double value = std::abs(j.dot(c));
      if (value >= out.corner_max_px) {
        out.corner_max_px = value;
        out.corner_max_se_px = std::sqrt(std::max(0.0, j.dot(cov * j)));
      }
    }
  }
  return out;
}

}  // namespace glmbslam::frontend
