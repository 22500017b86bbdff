#pragma once
// The contrast of the right camera relative to the left (stereo.gain_compensation). Cameras of a pair that
// expose or amplify independently see the same scene with different contrast (the EuRoC slice's right
// camera: 1/1.13 of the left's). The sub-pixel costs remove a brightness offset, not a gain, and a gain bends
// the SAD curve: on rendered frames with the right image at 0.7 of the left's contrast the centre fit's
// disparity bias grows from +0.03 to +0.08 px (tests/frontend/test_stereo_disparity_bias.cpp), which
// stretches the whole trajectory. The gain is estimated per frame from the descriptor matches' patches and
// the higher-contrast image of each level scaled down to the other's before the SAD search.
#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

namespace glmbslam::frontend {

/// A left/right patch pair at whole pixels of one pyramid level (the descriptor match before sub-pixel).
struct PatchPair {
  int level = 0;
  int xl = 0, yl = 0;  ///< left patch centre on that level
  int xr = 0;          ///< right patch centre on that level (same row)
};

/// σ_L / σ_R, the median over the pairs of the (2w+1)² patches' grey-level standard deviations, from at most
/// `max_samples` pairs spread evenly over the list; pairs whose patch leaves its image or is flat (σ < 2 grey
/// levels in either image) are skipped. NaN when fewer than `min_samples` pairs remain.
double estimate_right_gain(const std::vector<cv::Mat>& left_pyramid,
                           const std::vector<cv::Mat>& right_pyramid, const std::vector<PatchPair>& pairs,
                           int w, std::size_t max_samples = 300, std::size_t min_samples = 20);

/// The pyramid levels photometrically matched for a gain g = σ_L / σ_R: for g < 1 the right level becomes
/// g·R + (1 − g)·127.5, for g > 1 the left level L/g + (1 − 1/g)·127.5 (the image with more contrast is
/// scaled down, so nothing saturates). Levels are built on first use; with g = 1 the inputs are returned.
class ContrastMatchedLevels {
 public:
  ContrastMatchedLevels(const std::vector<cv::Mat>& left, const std::vector<cv::Mat>& right, double gain);

  const cv::Mat& left(int level);
  const cv::Mat& right(int level);

 private:
  const cv::Mat& scaled(const std::vector<cv::Mat>& source, std::vector<cv::Mat>& cache, int level,
                        double alpha);

  const std::vector<cv::Mat>& left_;
  const std::vector<cv::Mat>& right_;
  double gain_;
  std::vector<cv::Mat> left_cache_, right_cache_;
};

}  // namespace glmbslam::frontend
