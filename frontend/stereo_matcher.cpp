#include "frontend/stereo_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <opencv2/core/hal/intrin.hpp>

#include "frontend/stereo_gain.hpp"

namespace glmbslam::frontend {

namespace {

// SAD between (2w+1)² patches centred at (xl, y) in L and (xr, y) in R after removing the brightness offset
// c between them: Σ |L(p) − R(p') − c|. Caller guarantees the bounds.
int patch_sad_scalar(const cv::Mat& L, const cv::Mat& R, int xl, int xr, int y, int w, int c) {
  int sad = 0;
  for (int dy = -w; dy <= w; ++dy) {
    const uchar* pl = L.ptr<uchar>(y + dy) + xl - w;
    const uchar* pr = R.ptr<uchar>(y + dy) + xr - w;
    for (int dx = 0; dx <= 2 * w; ++dx) sad += std::abs(pl[dx] - pr[dx] - c);
  }
  return sad;
}

// Sum of the (2w+1)² patch centred at (x, y).
int patch_sum(const cv::Mat& I, int x, int y, int w) {
  int sum = 0;
  for (int dy = -w; dy <= w; ++dy) {
    const uchar* p = I.ptr<uchar>(y + dy) + x - w;
    for (int dx = 0; dx <= 2 * w; ++dx) sum += p[dx];
  }
  return sum;
}

// The brightness offset between the left patch at xl and the right patches at x = xr0 − radius … xr0 +
// radius (offsets[x − xr0 + radius]): the centre pixels' difference ("centre", ORB-SLAM2's), or the patch
// means' difference rounded to a grey level ("zero_mean"; the right patch sums slide over column sums).
void brightness_offsets(const cv::Mat& L, const cv::Mat& R, int xl, int xr0, int y, int w, int radius,
                        bool zero_mean, int* offsets, std::vector<int>& columns) {
  if (!zero_mean) {
    const int cl = L.at<uchar>(y, xl);
    for (int inc = -radius; inc <= radius; ++inc) offsets[inc + radius] = cl - R.at<uchar>(y, xr0 + inc);
    return;
  }
  const int n = (2 * w + 1) * (2 * w + 1);
  const int sum_l = patch_sum(L, xl, y, w);
  const int x0 = xr0 - radius - w, width = 2 * (radius + w) + 1;
  columns.assign(static_cast<std::size_t>(width), 0);
  for (int dy = -w; dy <= w; ++dy) {
    const uchar* p = R.ptr<uchar>(y + dy) + x0;
    for (int i = 0; i < width; ++i) columns[static_cast<std::size_t>(i)] += p[i];
  }
  int sum_r = 0;
  for (int i = 0; i < 2 * w + 1; ++i) sum_r += columns[static_cast<std::size_t>(i)];
  for (int inc = -radius; inc <= radius; ++inc) {
    if (inc > -radius) {
      const auto i = static_cast<std::size_t>(inc + radius);
      sum_r += columns[i + static_cast<std::size_t>(2 * w)] - columns[i - 1];
    }
    const int d = sum_l - sum_r;  // rounded to the nearest integer of d / n, halves away from zero
    offsets[inc + radius] = d >= 0 ? (2 * d + n) / (2 * n) : -((-2 * d + n) / (2 * n));
  }
}

// SAD of the patch at (xl, y) in L against the patches at (x, y) in R for x = xr0 − radius … xr0 + radius
// (sads[x − xr0 + radius]), each with its brightness offset. 16 pixels per row in SIMD registers when the
// patch fits (2w + 1 ≤ 16) and the 16-byte loads stay inside the rows; the scalar version otherwise (same
// result).
void sad_search(const cv::Mat& L, const cv::Mat& R, int xl, int xr0, int y, int w, int radius,
                const int* offsets, int* sads) {
#if CV_SIMD128
  if (2 * w + 1 <= 16 && xl - w + 16 <= L.cols && xr0 + radius - w + 16 <= R.cols) {
    alignas(16) std::int16_t lane_mask[16];
    for (int i = 0; i < 16; ++i) lane_mask[i] = i <= 2 * w ? -1 : 0;
    const cv::v_int16x8 mask_lo = cv::v_load(lane_mask), mask_hi = cv::v_load(lane_mask + 8);
    for (int inc = -radius; inc <= radius; ++inc) {
      const int xr = xr0 + inc;
      const cv::v_int16x8 c = cv::v_setall_s16(static_cast<short>(offsets[inc + radius]));
      cv::v_uint16x8 acc = cv::v_setzero_u16();
      for (int dy = -w; dy <= w; ++dy) {
        cv::v_uint16x8 l_lo, l_hi, r_lo, r_hi;
        cv::v_expand(cv::v_load(L.ptr<uchar>(y + dy) + xl - w), l_lo, l_hi);
        cv::v_expand(cv::v_load(R.ptr<uchar>(y + dy) + xr - w), r_lo, r_hi);
        const cv::v_int16x8 d_lo = cv::v_reinterpret_as_s16(l_lo) - cv::v_reinterpret_as_s16(r_lo) - c;
        const cv::v_int16x8 d_hi = cv::v_reinterpret_as_s16(l_hi) - cv::v_reinterpret_as_s16(r_hi) - c;
        acc += cv::v_reinterpret_as_u16(cv::v_reinterpret_as_s16(cv::v_abs(d_lo)) & mask_lo) +
               cv::v_reinterpret_as_u16(cv::v_reinterpret_as_s16(cv::v_abs(d_hi)) & mask_hi);
      }
      sads[inc + radius] = static_cast<int>(cv::v_reduce_sum(acc));
    }
    return;
  }
#endif
  for (int inc = -radius; inc <= radius; ++inc)
    sads[inc + radius] = patch_sad_scalar(L, R, xl, xr0 + inc, y, w, offsets[inc + radius]);
}

/// stereo.subpixel_refine lk: u_R refined by a one-dimensional Lucas–Kanade with a brightness offset,
///   min over (x_R, β) of Σ_window (I_R(x + x_R − x_L, y) + β − I_L(x, y))²,
/// Gauss–Newton from the fit's column, I_R linearly interpolated along the rectified row and its gradient the
/// interpolated central difference (β eliminated in closed form: the window's zero-mean residual and
/// gradient). A three-point fit to integer-shift costs is pulled towards whole pixels (pixel locking);
/// interpolating the image instead of the cost is not (rendered frames: bias +0.002 px, MAD 0.08 px against
/// the centre fit's +0.03 px and 0.36 px; tests/frontend/test_stereo_disparity_bias.cpp). The offset keeps
/// the left/right exposure difference out: OpenCV's calcOpticalFlowPyrLK, which has none, shortened the VO's
/// path on KITTI raw 0001 by 0.8 %. Returns false if the window leaves the image, the texture has no
/// horizontal gradient or the refinement moves more than one pixel from the start.
bool refine_column_lk(const cv::Mat& L, const cv::Mat& R, int xl, int yl, int w, double* xr) {
  const double start = *xr;
  double x = start;
  for (int it = 0; it < 10; ++it) {
    const int x0 = static_cast<int>(std::floor(x));  // integer part of the right column
    const double a = x - x0;
    if (yl - w < 0 || yl + w >= R.rows || x0 - w - 1 < 0 || x0 + w + 2 >= R.cols) return false;
    double sg = 0.0, sr = 0.0, sgg = 0.0, sgr = 0.0;
    for (int dy = -w; dy <= w; ++dy) {
      const uchar* lrow = L.ptr<uchar>(yl + dy);
      const uchar* rrow = R.ptr<uchar>(yl + dy);
      for (int dx = -w; dx <= w; ++dx) {
        const int c = x0 + dx;
        const double i0 = rrow[c], i1 = rrow[c + 1];
        const double g0 = 0.5 * (i1 - rrow[c - 1]), g1 = 0.5 * (rrow[c + 2] - i0);
        const double g = (1.0 - a) * g0 + a * g1;
        const double r = (1.0 - a) * i0 + a * i1 - lrow[xl + dx];
        sg += g;
        sr += r;
        sgg += g * g;
        sgr += g * r;
      }
    }
    const double n = (2.0 * w + 1.0) * (2.0 * w + 1.0);
    const double hgg = sgg - sg * sg / n, hgr = sgr - sg * sr / n;
    if (!(hgg > 1e-6 * n)) return false;
    const double step = -hgr / hgg;
    x += step;
    if (std::abs(x - start) > 1.0) return false;
    if (std::abs(step) < 1e-3) break;
  }
  *xr = x;
  return true;
}

// Sub-pixel offset of the minimum s2 from its neighbours s1 (left) and s3 (right), in (−1, 1) or outside
// when the fit fails: a parabola through the three (ORB-SLAM2's), or the equiangular fit — two lines of
// opposite slope, the interpolation matched to an L1 cost such as SAD (Shimizu & Okutomi 2005).
double subpixel_offset(double s1, double s2, double s3, bool equiangular) {
  if (equiangular) {
    const double m = std::max(s1, s3) - s2;
    return m > 0.0 ? 0.5 * (s1 - s3) / m : 0.0;
  }
  const double denom = 2.0 * (s1 + s3 - 2.0 * s2);
  return denom > 0.0 ? (s1 - s3) / denom : 0.0;
}

// The SAD search around xr0 and its sub-pixel fit with the given brightness model: the minimum at xr0 +
// best_inc + delta (pixels of the level) and its SAD; false when the minimum lies on the search border or the
// fit leaves (−1, 1).
bool subpixel_search(const cv::Mat& L, const cv::Mat& R, int xl, int xr0, int y, int w, int radius,
                     bool zero_mean, std::vector<int>& sads, std::vector<int>& offsets,
                     std::vector<int>& columns, int& best_inc, double& delta, int& best_sad) {
  brightness_offsets(L, R, xl, xr0, y, w, radius, zero_mean, offsets.data(), columns);
  sad_search(L, R, xl, xr0, y, w, radius, offsets.data(), sads.data());
  best_sad = std::numeric_limits<int>::max();
  best_inc = 0;
  for (int inc = -radius; inc <= radius; ++inc) {
    const int s = sads[static_cast<std::size_t>(inc + radius)];
    if (s < best_sad) {
      best_sad = s;
      best_inc = inc;
    }
  }
  if (best_inc == -radius || best_inc == radius) return false;
  const auto i = static_cast<std::size_t>(best_inc + radius);
  delta = subpixel_offset(sads[i - 1], sads[i], sads[i + 1], zero_mean);
  return delta >= -1.0 && delta <= 1.0;
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

  // Row index (compressed rows): each right keypoint is listed on every row within its band, each row's list
  // sorted by u so that the disparity range is one contiguous run.
  struct RowEntry {
    float u;
    int j;
  };
  std::vector<int> row_start(static_cast<std::size_t>(height) + 1, 0);
  const int nr = static_cast<int>(right.keypoints.size());
  std::vector<int> band_y0(static_cast<std::size_t>(nr)), band_y1(static_cast<std::size_t>(nr));
  for (int j = 0; j < nr; ++j) {
    const auto& k = right.keypoints[static_cast<std::size_t>(j)];
    const double r = config_.row_band_px * scales_[static_cast<std::size_t>(k.octave)];
    band_y0[static_cast<std::size_t>(j)] = std::max(0, static_cast<int>(std::floor(k.pt.y - r)));
    band_y1[static_cast<std::size_t>(j)] = std::min(height - 1, static_cast<int>(std::ceil(k.pt.y + r)));
    for (int y = band_y0[static_cast<std::size_t>(j)]; y <= band_y1[static_cast<std::size_t>(j)]; ++y) {
      ++row_start[static_cast<std::size_t>(y) + 1];
    }
  }
  for (int y = 0; y < height; ++y)
    row_start[static_cast<std::size_t>(y) + 1] += row_start[static_cast<std::size_t>(y)];
  std::vector<RowEntry> row_entries(static_cast<std::size_t>(row_start.back()));
  {
    std::vector<int> fill(row_start.begin(), row_start.end() - 1);
    for (int j = 0; j < nr; ++j) {
      const float u = right.keypoints[static_cast<std::size_t>(j)].pt.x;
      for (int y = band_y0[static_cast<std::size_t>(j)]; y <= band_y1[static_cast<std::size_t>(j)]; ++y) {
        row_entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(y)]++)] = {u, j};
      }
    }
  }
  for (int y = 0; y < height; ++y) {
    std::sort(row_entries.begin() + row_start[static_cast<std::size_t>(y)],
              row_entries.begin() + row_start[static_cast<std::size_t>(y) + 1],
              [](const RowEntry& a, const RowEntry& b) { return a.u < b.u; });
  }

  struct Candidate {
    int left, right, distance, sad;
    double u_r;
  };
  std::vector<Candidate> accepted;
  accepted.reserve(static_cast<std::size_t>(nl));
  const int w = config_.sad_half_window;
  const int radius = config_.sad_search_radius;
  std::vector<int> sads(static_cast<std::size_t>(2 * radius + 1)), offsets(sads.size()), columns;
  const bool zero_mean = config_.subpixel_cost == "zero_mean";
  const bool lucas_kanade = config_.subpixel_refine == "lk";
  struct Scored {
    float u;
    int distance;
  };
  std::vector<Scored> scored;
  struct DescriptorMatch {
    int left, right, distance;
    double u_right;  ///< the matched right keypoint's column (level 0)
  };
  std::vector<DescriptorMatch> descriptor_matches;
  descriptor_matches.reserve(static_cast<std::size_t>(nl));

  for (int i = 0; i < nl; ++i) {
    const auto& kl = left.keypoints[static_cast<std::size_t>(i)];
    const int row = cvRound(kl.pt.y);
    if (row < 0 || row >= height) continue;
    const double u_l = kl.pt.x;
    const double u_min = u_l - max_disparity;
    const double u_max = u_l - min_disparity;
    const uchar* dl = left.descriptors.ptr<uchar>(i);
    // Candidates: the row's entries with u in [u_min, u_max], octave and exact row band checked; distances
    // kept for the ratio test.
    const RowEntry* begin = row_entries.data() + row_start[static_cast<std::size_t>(row)];
    const RowEntry* end = row_entries.data() + row_start[static_cast<std::size_t>(row) + 1];
    begin = std::lower_bound(begin, end, u_min, [](const RowEntry& e, double u) { return e.u < u; });
    int best = std::numeric_limits<int>::max(), best_j = -1;
    double best_u = 0.0;
    scored.clear();
    for (const RowEntry* e = begin; e != end && e->u <= u_max; ++e) {
      const auto& kr = right.keypoints[static_cast<std::size_t>(e->j)];
      if (std::abs(kr.octave - kl.octave) > config_.max_octave_difference) continue;
      if (std::abs(kr.pt.y - kl.pt.y) > config_.row_band_px * scales_[static_cast<std::size_t>(kr.octave)])
        continue;
      const int d = hamming_distance(dl, right.descriptors.ptr<uchar>(e->j));
      scored.push_back({e->u, d});
      if (d < best || (d == best && e->j < best_j)) {  // ties: lowest right index
        best = d;
        best_j = e->j;
        best_u = e->u;
      }
    }
    if (best_j < 0 || best >= config_.max_hamming) continue;
    if (config_.ratio < 1.0) {  // second best among candidates at least 2 px away from the best
      int second = std::numeric_limits<int>::max();
      for (const Scored& c : scored) {
        if (std::abs(c.u - best_u) >= 2.0) second = std::min(second, c.distance);
      }
      if (second != std::numeric_limits<int>::max() && best >= config_.ratio * second) continue;
    }
    ++st.candidates;
    descriptor_matches.push_back({i, best_j, best, best_u});
  }

  // Each match's patches on the left keypoint's level, whole pixels; the right camera's contrast from them.
  std::vector<PatchPair> pairs;
  pairs.reserve(descriptor_matches.size());
  for (const DescriptorMatch& dm : descriptor_matches) {
    const auto& kl = left.keypoints[static_cast<std::size_t>(dm.left)];
    PatchPair p;
    p.level = std::min(kl.octave, levels - 1);
    const double scale = scales_[static_cast<std::size_t>(p.level)];
    p.xl = cvRound(kl.pt.x / scale);
    p.yl = cvRound(kl.pt.y / scale);
    p.xr = cvRound(dm.u_right / scale);
    pairs.push_back(p);
  }
  st.right_gain = estimate_right_gain(left.pyramid, right.pyramid, pairs, w);
  const double gain = config_.gain_compensation && std::isfinite(st.right_gain) ? st.right_gain : 1.0;
  ContrastMatchedLevels matched_levels(left.pyramid, right.pyramid, gain);

  for (std::size_t m = 0; m < descriptor_matches.size(); ++m) {
    // Sub-pixel u_R: SAD search on the left keypoint's level around the matched right column, then the
    // sub-pixel fit of stereo.subpixel_cost.
    const DescriptorMatch& dm = descriptor_matches[m];
    const PatchPair& p = pairs[m];
    const double scale = scales_[static_cast<std::size_t>(p.level)];
    const cv::Mat& IL = matched_levels.left(p.level);
    const cv::Mat& IR = matched_levels.right(p.level);
    const int xl = p.xl, yl = p.yl, xr0 = p.xr;
    if (yl - w < 0 || yl + w >= IL.rows || yl + w >= IR.rows || xl - w < 0 || xl + w >= IL.cols ||
        xr0 - radius - w < 0 || xr0 + radius + w >= IR.cols) {
      ++st.rejected_subpixel;
      continue;
    }
    // centre: one search; zero_mean: its own search, kept only where the centre cost's minimum lies within
    // one pixel of the level (an ambiguous minimum moves between the two brightness models)
    int best_inc = 0, best_sad = 0;
    double delta = 0.0;
    if (!subpixel_search(IL, IR, xl, xr0, yl, w, radius, false, sads, offsets, columns, best_inc, delta,
                         best_sad)) {
      ++st.rejected_subpixel;
      continue;
    }
    if (zero_mean) {
      const double centre_offset = best_inc + delta;
      if (!subpixel_search(IL, IR, xl, xr0, yl, w, radius, true, sads, offsets, columns, best_inc, delta,
                           best_sad) ||
          std::abs(best_inc + delta - centre_offset) > 1.0) {
        ++st.rejected_subpixel;
        continue;
      }
    }
    double xr = xr0 + best_inc + delta;
    if (lucas_kanade && !refine_column_lk(IL, IR, xl, yl, w, &xr)) {
      ++st.rejected_subpixel;
      continue;
    }
    const double u_r = scale * xr;
    const double disparity = left.keypoints[static_cast<std::size_t>(dm.left)].pt.x - u_r;
    if (disparity < min_disparity || disparity > max_disparity) {
      ++st.rejected_subpixel;
      continue;
    }
    accepted.push_back({dm.left, dm.right, dm.distance, best_sad, u_r});
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
