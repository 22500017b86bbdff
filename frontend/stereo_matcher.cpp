#include "frontend/stereo_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace glmbslam::frontend {

namespace {

// SAD between (2w+1)² patches centred at (xl, y) in L and (xr, y) in R, each patch made relative to its own
// centre pixel (robust to a brightness offset between the cameras). Caller guarantees the bounds.
int patch_sad(const cv::Mat& L, const cv::Mat& R, int xl, int xr, int y, int w) {
  const int cl = L.at<uchar>(y, xl);
  const int cr = R.at<uchar>(y, xr);
  int sad = 0;
  for (int dy = -w; dy <= w; ++dy) {
    const uchar* pl = L.ptr<uchar>(y + dy) + xl - w;
    const uchar* pr = R.ptr<uchar>(y + dy) + xr - w;
    for (int dx = 0; dx <= 2 * w; ++dx) sad += std::abs((pl[dx] - cl) - (pr[dx] - cr));
  }
  return sad;
}

}  // namespace

StereoMatcher::StereoMatcher(const StereoCamera& camera, const StereoMatchConfig& config,
                             std::vector<double> scales)
    : camera_(camera), config_(config), scales_(std::move(scales)) {}

StereoMeasurementList StereoMatcher::match(const OrbFeatures& left, const OrbFeatures& right,
                                           std::vector<int>* left_to_measurement,
                                           StereoMatchStats* stats) const {
  StereoMatchStats st;
  StereoMeasurementList out;
  const int nl = static_cast<int>(left.keypoints.size());
  if (left_to_measurement != nullptr) left_to_measurement->assign(static_cast<std::size_t>(nl), -1);
  if (nl == 0 || right.keypoints.empty() || left.pyramid.empty() || right.pyramid.empty()) {
    if (stats != nullptr) *stats = st;
    return out;
  }
  const int height = right.pyramid[0].rows;
  const double bf = camera_.bf();
  const double min_disparity = bf / config_.max_depth_m;
  const double max_disparity = bf / config_.min_depth_m;
  const int levels = static_cast<int>(std::min(left.pyramid.size(), right.pyramid.size()));

  // Row index: each right keypoint is listed on every row within its band.
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(height));
  for (int j = 0; j < static_cast<int>(right.keypoints.size()); ++j) {
    const auto& k = right.keypoints[static_cast<std::size_t>(j)];
    const double r = config_.row_band_px * scales_[static_cast<std::size_t>(k.octave)];
    const int y0 = std::max(0, static_cast<int>(std::floor(k.pt.y - r)));
    const int y1 = std::min(height - 1, static_cast<int>(std::ceil(k.pt.y + r)));
    for (int y = y0; y <= y1; ++y) rows[static_cast<std::size_t>(y)].push_back(j);
  }

  struct Candidate {
    int left, right, distance, sad;
    double u_r;
  };
  std::vector<Candidate> accepted;
  accepted.reserve(static_cast<std::size_t>(nl));
  const int w = config_.sad_half_window;
  const int radius = config_.sad_search_radius;
  std::vector<int> sads(static_cast<std::size_t>(2 * radius + 1));

  for (int i = 0; i < nl; ++i) {
    const auto& kl = left.keypoints[static_cast<std::size_t>(i)];
    const int row = cvRound(kl.pt.y);
    if (row < 0 || row >= height) continue;
    const double u_l = kl.pt.x;
    const double u_min = u_l - max_disparity;
    const double u_max = u_l - min_disparity;
    const uchar* dl = left.descriptors.ptr<uchar>(i);
    int best = std::numeric_limits<int>::max(), best_j = -1;
    double best_u = 0.0;
    for (int j : rows[static_cast<std::size_t>(row)]) {
      const auto& kr = right.keypoints[static_cast<std::size_t>(j)];
      if (std::abs(kr.octave - kl.octave) > config_.max_octave_difference) continue;
      if (kr.pt.x < u_min || kr.pt.x > u_max) continue;
      if (std::abs(kr.pt.y - kl.pt.y) > config_.row_band_px * scales_[static_cast<std::size_t>(kr.octave)])
        continue;
      const int d = hamming_distance(dl, right.descriptors.ptr<uchar>(j));
      if (d < best) {
        best = d;
        best_j = j;
        best_u = kr.pt.x;
      }
    }
    if (best_j < 0 || best >= config_.max_hamming) continue;
    if (config_.ratio < 1.0) {  // second best among candidates at least 2 px away from the best
      int second = std::numeric_limits<int>::max();
      for (int j : rows[static_cast<std::size_t>(row)]) {
        const auto& kr = right.keypoints[static_cast<std::size_t>(j)];
        if (j == best_j || std::abs(kr.octave - kl.octave) > config_.max_octave_difference) continue;
        if (kr.pt.x < u_min || kr.pt.x > u_max || std::abs(kr.pt.x - best_u) < 2.0) continue;
        if (std::abs(kr.pt.y - kl.pt.y) > config_.row_band_px * scales_[static_cast<std::size_t>(kr.octave)])
          continue;
        second = std::min(second, hamming_distance(dl, right.descriptors.ptr<uchar>(j)));
      }
      if (second != std::numeric_limits<int>::max() && best >= config_.ratio * second) continue;
    }
    ++st.candidates;

    // Sub-pixel u_R: SAD search on the left keypoint's level around the matched right column, parabola fit.
    const int level = std::min(kl.octave, levels - 1);
    const double scale = scales_[static_cast<std::size_t>(level)];
    const cv::Mat& IL = left.pyramid[static_cast<std::size_t>(level)];
    const cv::Mat& IR = right.pyramid[static_cast<std::size_t>(level)];
    const int xl = cvRound(kl.pt.x / scale);
    const int yl = cvRound(kl.pt.y / scale);
    const int xr0 = cvRound(best_u / scale);
    if (yl - w < 0 || yl + w >= IL.rows || yl + w >= IR.rows || xl - w < 0 || xl + w >= IL.cols ||
        xr0 - radius - w < 0 || xr0 + radius + w >= IR.cols) {
      ++st.rejected_subpixel;
      continue;
    }
    int best_sad = std::numeric_limits<int>::max(), best_inc = 0;
    for (int inc = -radius; inc <= radius; ++inc) {
      const int s = patch_sad(IL, IR, xl, xr0 + inc, yl, w);
      sads[static_cast<std::size_t>(inc + radius)] = s;
      if (s < best_sad) {
        best_sad = s;
        best_inc = inc;
      }
    }
    if (best_inc == -radius || best_inc == radius) {
      ++st.rejected_subpixel;
      continue;
    }
    const double s1 = sads[static_cast<std::size_t>(best_inc + radius - 1)];
    const double s2 = sads[static_cast<std::size_t>(best_inc + radius)];
    const double s3 = sads[static_cast<std::size_t>(best_inc + radius + 1)];
    const double denom = 2.0 * (s1 + s3 - 2.0 * s2);
    const double delta = denom > 0.0 ? (s1 - s3) / denom : 0.0;
    if (delta < -1.0 || delta > 1.0) {
      ++st.rejected_subpixel;
      continue;
    }
    const double u_r = scale * (xr0 + best_inc + delta);
    const double disparity = u_l - u_r;
    if (disparity < min_disparity || disparity > max_disparity) {
      ++st.rejected_subpixel;
      continue;
    }
    accepted.push_back({i, best_j, best, best_sad, u_r});
  }

  // Each right keypoint once: lowest Hamming distance (then lowest SAD) wins.
  std::vector<int> owner(right.keypoints.size(), -1);
  for (int a = 0; a < static_cast<int>(accepted.size()); ++a) {
    const auto& c = accepted[static_cast<std::size_t>(a)];
    int& o = owner[static_cast<std::size_t>(c.right)];
    if (o < 0) {
      o = a;
    } else {
      const auto& prev = accepted[static_cast<std::size_t>(o)];
      if (c.distance < prev.distance || (c.distance == prev.distance && c.sad < prev.sad)) o = a;
    }
  }
  std::vector<Candidate> unique;
  unique.reserve(accepted.size());
  for (int a = 0; a < static_cast<int>(accepted.size()); ++a) {
    if (owner[static_cast<std::size_t>(accepted[static_cast<std::size_t>(a)].right)] == a) {
      unique.push_back(accepted[static_cast<std::size_t>(a)]);
    }
  }
  st.rejected_subpixel += static_cast<int>(accepted.size() - unique.size());

  // Outliers relative to the frame's statistics: SAD far above the median.
  if (!unique.empty()) {
    std::vector<int> s;
    s.reserve(unique.size());
    for (const auto& c : unique) s.push_back(c.sad);
    std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(s.size() / 2), s.end());
    st.median_sad = s[s.size() / 2];
  }
  const double sad_limit = config_.outlier_sad_factor * std::max(st.median_sad, 1.0);
  out.reserve(unique.size());
  for (const auto& c : unique) {
    if (c.sad > sad_limit) {
      ++st.rejected_outlier;
      continue;
    }
    const auto& kl = left.keypoints[static_cast<std::size_t>(c.left)];
    StereoMeasurement m;
    m.z = Eigen::Vector3d(kl.pt.x, kl.pt.y, c.u_r);
    m.pixel_sigma = config_.pixel_sigma * scales_[static_cast<std::size_t>(kl.octave)];
    m.point = camera_.triangulate(m.z);
    m.point_covariance = camera_.triangulation_covariance(m.z, m.pixel_sigma);
    std::copy_n(left.descriptors.ptr<uchar>(c.left), 32, m.descriptor.begin());
    m.octave = kl.octave;
    m.response = kl.response;
    m.angle_deg = kl.angle;
    m.left_index = c.left;
    m.right_index = c.right;
    if (left_to_measurement != nullptr)
      (*left_to_measurement)[static_cast<std::size_t>(c.left)] = static_cast<int>(out.size());
    out.push_back(m);
  }
  st.accepted = static_cast<int>(out.size());
  if (stats != nullptr) *stats = st;
  return out;
}

}  // namespace glmbslam::frontend
