#pragma once
// Checks that a rectified stereo pair is row-aligned, from the frontend's own matches. The stereo matcher
// searches u_R along the left keypoint's row, so a right image shifted vertically (a calibration or
// rectification error) turns into horizontal errors on oblique texture, i.e. disparity and depth errors the
// noise model does not describe. Renders are aligned to 0.02 px; KITTI raw 2011_09_26 is not (drive 0001: the
// right image 0.26 px higher in the median, the fitted field below up to 1.7 px at the corners, mostly its xy
// term; docs/investigations.md).
//
// On every frame until `min_samples` are gathered, then on every `every_frames`-th, up to `max_points`
// level-0 matches (spread over the frame's list) are re-aligned in two dimensions: the left (2h+1)² patch at
// (u_L, v) against the right image around (u_R, v) by OpenCV's enhanced correlation coefficient
// (cv::findTransformECC, translation), which is invariant to the gain and offset between the two exposures.
// Its vertical component is the sample. The samples give the median offset and a field v_off(x, y) = c₀ + c₁x
// + c₂y + c₃xy over the image (x, y ∈ [−1, 1] from the left to the right edge and from the top to the
// bottom), fitted by least squares (a roll between the cameras makes the x term, a vertical scale the y term,
// a yaw or a tangential-distortion residual the xy term); `corner_max_px` is the largest |v_off| at the four
// corners, `corner_max_se_px` the standard error of that corner's value (from the fit's residuals): a short
// or textureless run leaves the field uncertain.
#include <array>
#include <cstddef>
#include <vector>

#include "frontend/stereo_frontend.hpp"

namespace glmbslam::frontend {

struct RectificationCheckOptions {
  int min_samples = 200;          ///< samples gathered on every frame before sampling every `every_frames`-th
  int max_gathering_frames = 20;  ///< ... on at most this many frames (textureless images give few samples)
  int every_frames = 25;          ///< frames between two sampled frames once min_samples are gathered
  int max_points = 25;  ///< matches sampled per sampled frame (≈ 0.25 ms each: 0.25 ms per frame on average)
  int half_window = 10;  ///< patch half size h (pixels)
  int margin = 3;        ///< vertical and horizontal search margin (pixels); larger offsets are not measured
};

struct RectificationSummary {
  std::size_t samples = 0;        ///< matches re-aligned
  std::size_t frames = 0;         ///< frames sampled
  double median_px = 0.0;         ///< median vertical offset of the right image (+: lower)
  std::array<double, 4> field{};  ///< c₀, c₁, c₂, c₃ of v_off(x, y) (pixels)
  double corner_max_px = 0.0;     ///< max |v_off| at the image corners
  double corner_max_se_px = 0.0;  ///< its standard error
  bool valid() const { return samples >= 50; }
};

class RectificationCheck {
 public:
  explicit RectificationCheck(const RectificationCheckOptions& options = {});

  /// Frame k of the run (sampled while fewer than min_samples are gathered, then when k is a multiple of
  /// every_frames); its pyramids and measurements.
  void add_frame(std::size_t k, const StereoFrameFeatures& frame);
  RectificationSummary summary() const;

 private:
  struct Sample {
    double x, y, dy;
  };
  RectificationCheckOptions options_;
  std::vector<Sample> samples_;
  std::size_t frames_ = 0;
};

}  // namespace glmbslam::frontend
