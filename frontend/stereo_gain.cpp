#include "frontend/stereo_gain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace glmbslam::frontend {

namespace {

// Grey-level standard deviation of the (2w+1)² patch centred at (x, y); the caller checks the bounds.
double patch_sigma(const cv::Mat& I, int x, int y, int w) {
  long sum = 0, sum_sq = 0;
  for (int dy = -w; dy <= w; ++dy) {
    const uchar* p = I.ptr<uchar>(y + dy) + x - w;
    for (int dx = 0; dx <= 2 * w; ++dx) {
      sum += p[dx];
      sum_sq += static_cast<long>(p[dx]) * p[dx];
    }
  }
  const double n = (2.0 * w + 1.0) * (2.0 * w + 1.0);
  const double mean = static_cast<double>(sum) / n;
  return std::sqrt(std::max(0.0, static_cast<double>(sum_sq) / n - mean * mean));
}

bool patch_inside(const cv::Mat& I, int x, int y, int w) {
  return x - w >= 0 && y - w >= 0 && x + w < I.cols && y + w < I.rows;
}

}  // namespace

double estimate_right_gain(const std::vector<cv::Mat>& left_pyramid,
                           const std::vector<cv::Mat>& right_pyramid, const std::vector<PatchPair>& pairs,
                           int w, std::size_t max_samples, std::size_t min_samples) {
  constexpr double kFlatSigma = 2.0;  // grey levels: a flat patch's ratio is the noise's, not the gain's
  const std::size_t levels = std::min(left_pyramid.size(), right_pyramid.size());
  const std::size_t stride = std::max<std::size_t>(1, pairs.size() / std::max<std::size_t>(1, max_samples));
  std::vector<double> ratios;
  ratios.reserve(pairs.size() / stride + 1);
  for (std::size_t i = 0; i < pairs.size(); i += stride) {
    const PatchPair& p = pairs[i];
    if (p.level < 0 || static_cast<std::size_t>(p.level) >= levels) continue;
    const cv::Mat& L = left_pyramid[static_cast<std::size_t>(p.level)];
    const cv::Mat& R = right_pyramid[static_cast<std::size_t>(p.level)];
    if (!patch_inside(L, p.xl, p.yl, w) || !patch_inside(R, p.xr, p.yl, w)) continue;
    const double sl = patch_sigma(L, p.xl, p.yl, w), sr = patch_sigma(R, p.xr, p.yl, w);
    if (sl < kFlatSigma || sr < kFlatSigma) continue;
    ratios.push_back(sl / sr);
  }
  if (ratios.size() < min_samples) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2);
  std::nth_element(ratios.begin(), mid, ratios.end());
  return *mid;
}

ContrastMatchedLevels::ContrastMatchedLevels(const std::vector<cv::Mat>& left,
                                             const std::vector<cv::Mat>& right, double gain)
    : left_(left), right_(right), gain_(gain), left_cache_(left.size()), right_cache_(right.size()) {}

const cv::Mat& ContrastMatchedLevels::scaled(const std::vector<cv::Mat>& source, std::vector<cv::Mat>& cache,
                                             int level, double alpha) {
  const auto l = static_cast<std::size_t>(level);
  if (cache[l].empty()) source[l].convertTo(cache[l], -1, alpha, (1.0 - alpha) * 127.5);
  return cache[l];
}

const cv::Mat& ContrastMatchedLevels::left(int level) {
  if (gain_ <= 1.0) return left_[static_cast<std::size_t>(level)];
  return scaled(left_, left_cache_, level, 1.0 / gain_);
}

const cv::Mat& ContrastMatchedLevels::right(int level) {
  if (gain_ >= 1.0) return right_[static_cast<std::size_t>(level)];
  return scaled(right_, right_cache_, level, gain_);
}

}  // namespace glmbslam::frontend
