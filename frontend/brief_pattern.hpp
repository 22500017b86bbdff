#pragma once
// Steered BRIEF (Calonder et al. 2010; Rublee et al. 2011, sec. 4): 256 binary intensity tests between point
// pairs of the 31×31 patch around a keypoint, on the Gaussian-smoothed image, the pairs rotated by the
// keypoint's orientation. The pairs are drawn once, deterministically (fixed SplitMix64 sequence,
// Box–Muller), from the isotropic Gaussian of BRIEF's sampling strategy G II (σ = 31/5 px), kept inside a
// disc of radius kBriefRadius so that every rotation stays inside the patch. The rotated pattern is tabulated
// for kBriefAngleBins orientations (rounded to whole pixels), so a descriptor costs 512 table look-ups.
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace glmbslam::frontend {

constexpr int kBriefPairs = 256;
constexpr int kBriefRadius = 13;      ///< largest distance of a test point from the keypoint (pixels)
constexpr int kBriefAngleBins = 120;  ///< orientation bins of the tabulated rotated pattern (3° each)

class BriefPattern {
 public:
  BriefPattern();

  /// 32-byte descriptor of the keypoint at integer pixel (x, y) of `smoothed` (8-bit, one channel) with
  /// orientation `angle_deg`. Caller guarantees (x, y) is at least kBriefRadius + 1 pixels from the border.
  void describe(const cv::Mat& smoothed, int x, int y, float angle_deg, std::uint8_t* out) const;

  /// Address offsets of the rotated pattern for an image with rows `step` bytes apart:
  /// offsets[bin · 512 + 2i + {0, 1}] for the two points of pair i.
  std::vector<int> offsets(int step) const;

  /// Same descriptor as describe() from a table made by offsets(step) for the image `center` points into.
  void describe(const std::uint8_t* center, const std::vector<int>& offsets, float angle_deg,
                std::uint8_t* out) const;

  /// The unrotated pairs (x1, y1, x2, y2), for tests.
  const std::vector<std::array<float, 4>>& pairs() const { return pairs_; }

 private:
  std::vector<std::array<float, 4>> pairs_;
  /// rotated_[bin][4 * i + {0,1,2,3}] = rounded (x1, y1, x2, y2) of pair i rotated by bin · 360° / bins.
  std::vector<std::array<std::int8_t, 4 * kBriefPairs>> rotated_;
};

}  // namespace glmbslam::frontend
