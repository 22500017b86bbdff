#pragma once
// Stereo matching of ORB keypoints along rectified rows, with sub-pixel refinement of u_R and triangulation.
#include <limits>
#include <vector>

#include "frontend/frontend_config.hpp"
#include "frontend/orb_extractor.hpp"
#include "frontend/stereo_measurement.hpp"
#include "frontend/stereo_projection.hpp"

namespace glmbslam::frontend {

/// Per-frame matching statistics (for logs and metrics).
struct StereoMatchStats {
  int candidates = 0;         ///< left keypoints with a descriptor match under the thresholds
  int rejected_subpixel = 0;  ///< refinement failed (border, minimum at the search edge, bad parabola)
  int rejected_outlier = 0;   ///< SAD above outlier_sad_factor × median
  int accepted = 0;
  double median_sad = 0.0;
  /// the right camera's contrast relative to the left's, σ_L / σ_R (stereo_gain.hpp; NaN when the frame
  /// had too few textured matches), levelled out before the sub-pixel search when gain_compensation is on
  double right_gain = std::numeric_limits<double>::quiet_NaN();
};

class StereoMatcher {
 public:
  /// `scales` are scale_factor^level of the extractor that produced the features.
  StereoMatcher(const StereoCamera& camera, const StereoMatchConfig& config, std::vector<double> scales);

  /// Matches left to right keypoints. For each left keypoint, the candidates are the right keypoints whose
  /// row lies within row_band_px · scale^octave, whose octave differs by at most max_octave_difference, and
  /// whose disparity u_L − u_R lies in [f·b/max_depth, f·b/min_depth]. The best Hamming distance must be
  /// under max_hamming and pass the ratio test; with gain_compensation the right camera's contrast relative
  /// to the left's is estimated from these matches' patches and levelled out (stereo_gain.hpp); u_R is then
  /// refined by a SAD search on the keypoint's pyramid level with the sub-pixel fit of subpixel_cost (centre:
  /// parabola; zero_mean: equiangular, kept where the centre cost's minimum lies within one pixel of the
  /// level); each right keypoint is used once (lowest distance wins); matches whose SAD exceeds
  /// outlier_sad_factor × the frame's median SAD are dropped.
  /// `left_to_measurement` (optional) receives, for every left keypoint, the index of its measurement or −1.
  StereoMeasurementList match(const OrbFeatures& left, const OrbFeatures& right,
                              std::vector<int>* left_to_measurement = nullptr,
                              StereoMatchStats* stats = nullptr) const;

  const StereoCamera& camera() const { return camera_; }

 private:
  StereoCamera camera_;
  StereoMatchConfig config_;
  std::vector<double> scales_;
};

}  // namespace glmbslam::frontend
