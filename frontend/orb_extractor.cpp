#include "frontend/orb_extractor.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace glmbslam::frontend {

namespace {

constexpr int kHalfPatch = 15;  // orientation patch radius (ORB's 31-pixel patch)

// Intensity-centroid orientation (Rublee et al. 2011, eq. 2-3) on a circular patch, degrees in [0, 360).
float intensity_centroid_angle(const cv::Mat& image, const cv::Point2f& pt, const std::vector<int>& umax) {
  int m01 = 0;
  int m10 = 0;
  const uchar* center = &image.at<uchar>(cvRound(pt.y), cvRound(pt.x));
  for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * center[u];
  const int step = static_cast<int>(image.step1());
  for (int v = 1; v <= kHalfPatch; ++v) {
    int v_sum = 0;
    const int d = umax[v];
    for (int u = -d; u <= d; ++u) {
      const int plus = center[u + v * step];
      const int minus = center[u - v * step];
      v_sum += plus - minus;
      m10 += u * (plus + minus);
    }
    m01 += v * v_sum;
  }
  return cv::fastAtan2(static_cast<float>(m01), static_cast<float>(m10));
}

}  // namespace

OrbExtractor::OrbExtractor(const OrbConfig& config) : config_(config) {
  const int L = config_.levels;
  scales_.resize(L);
  for (int l = 0; l < L; ++l) scales_[l] = std::pow(config_.scale_factor, l);
  // Budget per level proportional to the level's area share: n_l ∝ (1/s)^l (geometric series).
  level_budget_.assign(L, 0);
  const double f = 1.0 / config_.scale_factor;
  double per = config_.features * (1.0 - f) / (1.0 - std::pow(f, L));
  int total = 0;
  for (int l = 0; l < L - 1; ++l) {
    level_budget_[l] = static_cast<int>(std::lround(per));
    total += level_budget_[l];
    per *= f;
  }
  level_budget_[L - 1] = std::max(0, config_.features - total);

  umax_.resize(kHalfPatch + 1);
  const int vmax = cvFloor(kHalfPatch * std::sqrt(2.0) / 2 + 1);
  const int vmin = cvCeil(kHalfPatch * std::sqrt(2.0) / 2);
  for (int v = 0; v <= vmax; ++v) umax_[v] = cvRound(std::sqrt(double(kHalfPatch * kHalfPatch - v * v)));
  for (int v = kHalfPatch, v0 = 0; v >= vmin; --v) {  // make the patch symmetric
    while (umax_[v0] == umax_[v0 + 1]) ++v0;
    umax_[v] = v0;
    ++v0;
  }
  orb_ = cv::ORB::create(config_.features, static_cast<float>(config_.scale_factor), config_.levels,
                         config_.edge_threshold, 0, 2, cv::ORB::FAST_SCORE, 31, config_.fast_threshold);
}

void OrbExtractor::detect_level(const cv::Mat& img, int level, int budget,
                                std::vector<cv::KeyPoint>& out) const {
  const int edge = config_.edge_threshold;
  const int min_x = edge - 3, min_y = edge - 3;
  const int max_x = img.cols - edge + 3, max_y = img.rows - edge + 3;
  if (max_x - min_x < 16 || max_y - min_y < 16 || budget <= 0) return;
  const int cols = std::max(1, (max_x - min_x) / config_.cell_size);
  const int rows = std::max(1, (max_y - min_y) / config_.cell_size);
  const int cell_w = static_cast<int>(std::ceil(double(max_x - min_x) / cols));
  const int cell_h = static_cast<int>(std::ceil(double(max_y - min_y) / rows));

  std::vector<std::vector<cv::KeyPoint>> cells(static_cast<std::size_t>(rows * cols));
  std::vector<cv::KeyPoint> kps;
  for (int r = 0; r < rows; ++r) {
    const int y0 = min_y + r * cell_h;
    if (y0 >= max_y - 6) continue;
    const int y1 = std::min(y0 + cell_h + 6, max_y);
    for (int c = 0; c < cols; ++c) {
      const int x0 = min_x + c * cell_w;
      if (x0 >= max_x - 6) continue;
      const int x1 = std::min(x0 + cell_w + 6, max_x);
      const cv::Mat roi = img(cv::Range(y0, y1), cv::Range(x0, x1));
      kps.clear();
      cv::FAST(roi, kps, config_.fast_threshold, true);
      if (kps.empty() && config_.min_fast_threshold < config_.fast_threshold) {
        cv::FAST(roi, kps, config_.min_fast_threshold, true);
      }
      auto& cell = cells[static_cast<std::size_t>(r * cols + c)];
      for (auto& k : kps) {
        k.pt.x += static_cast<float>(x0);
        k.pt.y += static_cast<float>(y0);
        cell.push_back(k);
      }
      std::sort(cell.begin(), cell.end(),
                [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
    }
  }
  // Round robin over the cells: rank 0 of every cell, then rank 1, ... until the level's budget is spent.
  // Within the last (partial) rank the strongest corners win.
  std::vector<cv::KeyPoint> selected;
  selected.reserve(static_cast<std::size_t>(budget));
  std::vector<cv::KeyPoint> rank_pool;
  for (std::size_t rank = 0; static_cast<int>(selected.size()) < budget; ++rank) {
    rank_pool.clear();
    for (const auto& cell : cells) {
      if (cell.size() > rank) rank_pool.push_back(cell[rank]);
    }
    if (rank_pool.empty()) break;
    const std::size_t room = static_cast<std::size_t>(budget) - selected.size();
    if (rank_pool.size() > room) {
      std::nth_element(rank_pool.begin(), rank_pool.begin() + static_cast<std::ptrdiff_t>(room),
                       rank_pool.end(),
                       [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
      rank_pool.resize(room);
    }
    selected.insert(selected.end(), rank_pool.begin(), rank_pool.end());
  }
  const float scale = static_cast<float>(scales_[static_cast<std::size_t>(level)]);
  for (auto& k : selected) {
    k.angle = intensity_centroid_angle(img, k.pt, umax_);
    k.octave = level;
    k.size = 31.0f * scale;
    k.pt *= scale;  // level-0 coordinates
    out.push_back(k);
  }
}

OrbFeatures OrbExtractor::extract(const cv::Mat& image) const {
  OrbFeatures f;
  if (image.empty()) return f;
  cv::Mat gray;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  } else {
    gray = image;
  }
  if (gray.depth() != CV_8U) gray.convertTo(gray, CV_8U);

  f.pyramid.resize(static_cast<std::size_t>(config_.levels));
  f.pyramid[0] = gray;
  for (int l = 1; l < config_.levels; ++l) {
    const cv::Size sz(cvRound(gray.cols / scales_[l]), cvRound(gray.rows / scales_[l]));
    if (sz.width < 2 || sz.height < 2) {
      f.pyramid.resize(static_cast<std::size_t>(l));
      break;
    }
    cv::resize(f.pyramid[l - 1], f.pyramid[l], sz, 0, 0, cv::INTER_LINEAR);
  }
  f.keypoints.reserve(static_cast<std::size_t>(config_.features));
  for (std::size_t l = 0; l < f.pyramid.size(); ++l) {
    detect_level(f.pyramid[l], static_cast<int>(l), level_budget_[l], f.keypoints);
  }
  if (f.keypoints.empty()) {
    f.descriptors.create(0, 32, CV_8U);
    return f;
  }
  orb_->compute(gray, f.keypoints, f.descriptors);
  return f;
}

}  // namespace glmbslam::frontend
