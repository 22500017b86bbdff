#include "frontend/orb_extractor.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace glmbslam::frontend {

namespace {

constexpr int kHalfPatch = 15;  // orientation patch radius (ORB's 31-pixel patch)

// Intensity-centroid orientation (Rublee et al. 2011, eq. 2-3) on a circular patch, degrees in [0, 360).
float intensity_centroid_angle(const cv::Mat& image, int x, int y, const std::vector<int>& umax) {
  int m01 = 0;
  int m10 = 0;
  const uchar* center = &image.at<uchar>(y, x);
  for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * center[u];
  const int step = static_cast<int>(image.step1());
  for (int v = 1; v <= kHalfPatch; ++v) {
    int v_sum = 0;
    const int d = umax[static_cast<std::size_t>(v)];
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

/// The circular patch as per-row weight vectors for SIMD dot products: row v (−15 … 15) covers the 32 pixels
/// u = −15 … 16 of that row; weight_u = u and weight_v = v inside the circle (|u| ≤ umax[|v|]), 0 outside.
struct OrbExtractor::CentroidWeights {
  alignas(16) std::int16_t weight_u[2 * kHalfPatch + 1][32];
  alignas(16) std::int16_t weight_v[2 * kHalfPatch + 1][32];
};

namespace {

// The same moments as intensity_centroid_angle with 128-bit integer dot products (identical result). Needs
// 16 pixels of room right of the keypoint and 15 on the other sides (edge_threshold ≥ 17).
float intensity_centroid_angle_simd(const cv::Mat& image, int x, int y,
                                    const OrbExtractor::CentroidWeights& w) {
#if CV_SIMD128
  const int step = static_cast<int>(image.step1());
  const uchar* row = &image.at<uchar>(y, x) - kHalfPatch * step - kHalfPatch;
  cv::v_int32x4 acc_u = cv::v_setzero_s32(), acc_v = cv::v_setzero_s32();
  for (int r = 0; r <= 2 * kHalfPatch; ++r, row += step) {
    cv::v_uint16x8 p0, p1, p2, p3;
    cv::v_expand(cv::v_load(row), p0, p1);
    cv::v_expand(cv::v_load(row + 16), p2, p3);
    const cv::v_int16x8 q0 = cv::v_reinterpret_as_s16(p0), q1 = cv::v_reinterpret_as_s16(p1);
    const cv::v_int16x8 q2 = cv::v_reinterpret_as_s16(p2), q3 = cv::v_reinterpret_as_s16(p3);
    const std::int16_t* wu = w.weight_u[r];
    const std::int16_t* wv = w.weight_v[r];
    acc_u += cv::v_dotprod(q0, cv::v_load(wu)) + cv::v_dotprod(q1, cv::v_load(wu + 8)) +
             cv::v_dotprod(q2, cv::v_load(wu + 16)) + cv::v_dotprod(q3, cv::v_load(wu + 24));
    acc_v += cv::v_dotprod(q0, cv::v_load(wv)) + cv::v_dotprod(q1, cv::v_load(wv + 8)) +
             cv::v_dotprod(q2, cv::v_load(wv + 16)) + cv::v_dotprod(q3, cv::v_load(wv + 24));
  }
  return cv::fastAtan2(static_cast<float>(cv::v_reduce_sum(acc_v)),
                       static_cast<float>(cv::v_reduce_sum(acc_u)));
#else
  (void)image;
  (void)x;
  (void)y;
  (void)w;
  return 0.0f;
#endif
}

bool stronger(const cv::KeyPoint& a, const cv::KeyPoint& b) {
  return a.response > b.response;
}

}  // namespace

OrbExtractor::OrbExtractor(const OrbConfig& config) : config_(config) {
  const int L = config_.levels;
  scales_.resize(static_cast<std::size_t>(L));
  for (int l = 0; l < L; ++l) scales_[static_cast<std::size_t>(l)] = std::pow(config_.scale_factor, l);
  // Budget per level proportional to the level's area share: n_l ∝ (1/s)^l (geometric series).
  level_budget_.assign(static_cast<std::size_t>(L), 0);
  const double f = 1.0 / config_.scale_factor;
  double per = config_.features * (1.0 - f) / (1.0 - std::pow(f, L));
  int total = 0;
  for (int l = 0; l < L - 1; ++l) {
    level_budget_[static_cast<std::size_t>(l)] = static_cast<int>(std::lround(per));
    total += level_budget_[static_cast<std::size_t>(l)];
    per *= f;
  }
  level_budget_[static_cast<std::size_t>(L - 1)] = std::max(0, config_.features - total);

  umax_.resize(kHalfPatch + 1);
  const int vmax = cvFloor(kHalfPatch * std::sqrt(2.0) / 2 + 1);
  const int vmin = cvCeil(kHalfPatch * std::sqrt(2.0) / 2);
  for (int v = 0; v <= vmax; ++v) {
    umax_[static_cast<std::size_t>(v)] = cvRound(std::sqrt(double(kHalfPatch * kHalfPatch - v * v)));
  }
  for (int v = kHalfPatch, v0 = 0; v >= vmin; --v) {  // make the patch symmetric
    while (umax_[static_cast<std::size_t>(v0)] == umax_[static_cast<std::size_t>(v0 + 1)]) ++v0;
    umax_[static_cast<std::size_t>(v)] = v0;
    ++v0;
  }
  auto weights = std::make_shared<CentroidWeights>();
  for (int v = -kHalfPatch; v <= kHalfPatch; ++v) {
    const int d = umax_[static_cast<std::size_t>(std::abs(v))];
    for (int i = 0; i < 32; ++i) {
      const int u = i - kHalfPatch;
      const bool inside = std::abs(u) <= d;
      weights->weight_u[v + kHalfPatch][i] = static_cast<std::int16_t>(inside ? u : 0);
      weights->weight_v[v + kHalfPatch][i] = static_cast<std::int16_t>(inside ? v : 0);
    }
  }
  centroid_weights_ = std::move(weights);
  fixed_step_offsets_ = pattern_.offsets(kSmoothStep);
}

void OrbExtractor::detect_level(const cv::Mat& img, int budget, std::vector<cv::KeyPoint>& out) const {
  // Corners are detected in [edge − 3, size − edge + 3) (FAST needs 3 pixels of margin), so every corner is
  // at least `edge` pixels from the border: room for the orientation patch and the BRIEF pattern.
  const int edge = config_.edge_threshold;
  const int min_x = edge - 3, min_y = edge - 3;
  const int max_x = img.cols - edge + 3, max_y = img.rows - edge + 3;
  if (max_x - min_x < 16 || max_y - min_y < 16 || budget <= 0) return;
  const int cols = std::max(1, (max_x - min_x) / config_.cell_size);
  const int rows = std::max(1, (max_y - min_y) / config_.cell_size);
  const int cell_w = static_cast<int>(std::ceil(double(max_x - min_x) / cols));
  const int cell_h = static_cast<int>(std::ceil(double(max_y - min_y) / rows));
  auto cell_of = [&](const cv::KeyPoint& k) {
    const int cx = std::min(cols - 1, (static_cast<int>(k.pt.x) - min_x) / cell_w);
    const int cy = std::min(rows - 1, (static_cast<int>(k.pt.y) - min_y) / cell_h);
    return cy * cols + cx;
  };

  // One FAST pass over the whole level.
  std::vector<cv::KeyPoint> kps;
  cv::FAST(img(cv::Range(min_y, max_y), cv::Range(min_x, max_x)), kps, config_.fast_threshold, true);
  std::vector<int> count(static_cast<std::size_t>(rows * cols), 0);
  const std::size_t first_pass = kps.size();
  for (auto& k : kps) {
    k.pt.x += static_cast<float>(min_x);
    k.pt.y += static_cast<float>(min_y);
    ++count[static_cast<std::size_t>(cell_of(k))];
  }
  // The lower threshold in the cells left empty: one FAST call per run of consecutive empty cells of a grid
  // row, on a window 3 px wider on each side than the run (so corners on the cells' own borders are found);
  // only corners inside empty cells are kept.
  if (config_.min_fast_threshold < config_.fast_threshold) {
    std::vector<cv::KeyPoint> extra;
    for (int r = 0; r < rows; ++r) {
      const int y0 = min_y + r * cell_h;
      if (y0 >= max_y - 6) continue;
      for (int c = 0; c < cols;) {
        if (count[static_cast<std::size_t>(r * cols + c)] > 0) {
          ++c;
          continue;
        }
        int c_end = c + 1;
        while (c_end < cols && count[static_cast<std::size_t>(r * cols + c_end)] == 0) ++c_end;
        const int x0 = min_x + c * cell_w;
        const int x1 = std::min(max_x, min_x + c_end * cell_w);
        const int first_cell = r * cols + c, end_cell = r * cols + c_end;
        c = c_end;
        if (x0 >= max_x - 6) continue;
        const int wx0 = std::max(min_x, x0 - 3), wy0 = std::max(min_y, y0 - 3);
        const int wx1 = std::min(max_x, x1 + 3), wy1 = std::min(max_y, y0 + cell_h + 3);
        if (wx1 - wx0 < 7 || wy1 - wy0 < 7) continue;
        extra.clear();
        cv::FAST(img(cv::Range(wy0, wy1), cv::Range(wx0, wx1)), extra, config_.min_fast_threshold, true);
        for (auto& k : extra) {
          k.pt.x += static_cast<float>(wx0);
          k.pt.y += static_cast<float>(wy0);
          if (k.pt.x < x0 || k.pt.x >= x1 || k.pt.y < y0 || k.pt.y >= y0 + cell_h) continue;
          const int cell = cell_of(k);
          if (cell < first_cell || cell >= end_cell) continue;
          kps.push_back(k);
        }
      }
    }
    for (std::size_t i = first_pass; i < kps.size(); ++i) ++count[static_cast<std::size_t>(cell_of(kps[i]))];
  }
  // Bucket by cell (counting sort), strongest first within each cell.
  const std::size_t ncells = count.size();
  std::vector<int> start(ncells + 1, 0);
  for (std::size_t c = 0; c < ncells; ++c) start[c + 1] = start[c] + count[c];
  std::vector<cv::KeyPoint> bucketed(kps.size());
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (const auto& k : kps)
      bucketed[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of(k))]++)] = k;
  }
  for (std::size_t c = 0; c < ncells; ++c) {
    std::sort(bucketed.begin() + start[c], bucketed.begin() + start[c + 1], stronger);
  }
  // Round robin over the cells: rank 0 of every cell, then rank 1, ... until the level's budget is spent.
  // Within the last (partial) rank the strongest corners win.
  const std::size_t first = out.size();
  std::vector<cv::KeyPoint> rank_pool;
  for (int rank = 0; static_cast<int>(out.size() - first) < budget; ++rank) {
    rank_pool.clear();
    for (std::size_t c = 0; c < ncells; ++c) {
      if (count[c] > rank) rank_pool.push_back(bucketed[static_cast<std::size_t>(start[c] + rank)]);
    }
    if (rank_pool.empty()) break;
    const std::size_t room = static_cast<std::size_t>(budget) - (out.size() - first);
    if (rank_pool.size() > room) {
      std::nth_element(rank_pool.begin(), rank_pool.begin() + static_cast<std::ptrdiff_t>(room),
                       rank_pool.end(), stronger);
      rank_pool.resize(room);
    }
    out.insert(out.end(), rank_pool.begin(), rank_pool.end());
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
    const double s = scales_[static_cast<std::size_t>(l)];
    const cv::Size sz(cvRound(gray.cols / s), cvRound(gray.rows / s));
    if (sz.width < 2 || sz.height < 2) {
      f.pyramid.resize(static_cast<std::size_t>(l));
      break;
    }
    cv::resize(f.pyramid[static_cast<std::size_t>(l - 1)], f.pyramid[static_cast<std::size_t>(l)], sz, 0, 0,
               cv::INTER_LINEAR);
  }
  f.keypoints.reserve(static_cast<std::size_t>(config_.features));
  f.descriptors.create(config_.features, 32, CV_8U);
  // The smoothed level lives in a per-thread buffer with a fixed row step, so the rotated BRIEF pattern is a
  // precomputed table of address offsets (wider images use the generic path).
  thread_local std::vector<uchar> smooth_buffer;
  const bool fixed_step = gray.cols + 1 <= kSmoothStep;
  if (fixed_step && smooth_buffer.size() < static_cast<std::size_t>(gray.rows) * kSmoothStep) {
    smooth_buffer.resize(static_cast<std::size_t>(gray.rows) * kSmoothStep);
  }
  for (std::size_t l = 0; l < f.pyramid.size(); ++l) {
    const cv::Mat& img = f.pyramid[l];
    const std::size_t first = f.keypoints.size();
    detect_level(img, level_budget_[l], f.keypoints);
    if (f.keypoints.size() == first) continue;
    // Descriptors on the smoothed level (7×7 Gaussian, σ = 2, as ORB), orientation on the raw level.
    cv::Mat smoothed =
        fixed_step ? cv::Mat(img.rows, img.cols, CV_8U, smooth_buffer.data(), kSmoothStep) : cv::Mat();
    cv::GaussianBlur(img, smoothed, cv::Size(7, 7), 2, 2, cv::BORDER_REFLECT_101);
    const float scale = static_cast<float>(scales_[l]);
    const bool simd_centroid = CV_SIMD128 && config_.edge_threshold >= kHalfPatch + 2;
    for (std::size_t i = first; i < f.keypoints.size(); ++i) {
      cv::KeyPoint& k = f.keypoints[i];
      const int x = static_cast<int>(k.pt.x), y = static_cast<int>(k.pt.y);  // FAST corners are integral
      k.angle = simd_centroid ? intensity_centroid_angle_simd(img, x, y, *centroid_weights_)
                              : intensity_centroid_angle(img, x, y, umax_);
      k.octave = static_cast<int>(l);
      k.size = 31.0f * scale;
      k.pt *= scale;  // level-0 coordinates
      std::uint8_t* out = f.descriptors.ptr<std::uint8_t>(static_cast<int>(i));
      if (fixed_step) {
        pattern_.describe(smoothed.ptr<uchar>(y) + x, fixed_step_offsets_, k.angle, out);
      } else {
        pattern_.describe(smoothed, x, y, k.angle, out);
      }
    }
  }
  f.descriptors = f.descriptors.rowRange(0, static_cast<int>(f.keypoints.size()));
  return f;
}

}  // namespace glmbslam::frontend
