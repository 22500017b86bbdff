#pragma once
// ORB features spread over the image. Per pyramid level: one FAST pass (with non-maximum suppression) over
// the level, corners bucketed into a grid of cells, a second FAST pass with the lower threshold only in the
// cells the first left empty; the level keeps its share of the feature budget by taking the strongest corner
// of every cell in turn (round robin over cells). Only the kept corners get an orientation (intensity
// centroid) and a steered BRIEF descriptor (256 point-pair tests on the Gaussian-smoothed level, the pattern
// rotated to the keypoint's orientation; see brief_pattern.hpp).
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "frontend/brief_pattern.hpp"
#include "frontend/frontend_config.hpp"

namespace glmbslam::frontend {

/// Keypoints of one image (coordinates at level 0; octave = pyramid level) with their 32-byte descriptors
/// (row i of `descriptors` belongs to keypoints[i]) and the image pyramid they were found on.
struct OrbFeatures {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;           ///< N × 32, CV_8U
  std::vector<cv::Mat> pyramid;  ///< level images, pyramid[0] is the input image
};

class OrbExtractor {
 public:
  explicit OrbExtractor(const OrbConfig& config);

  /// Extracts features from an 8-bit grayscale image (a 3-channel image is converted). An empty image gives
  /// no features. Const and free of shared mutable state: one extractor may serve concurrent images.
  OrbFeatures extract(const cv::Mat& image) const;

  /// scale_factor^level for each level.
  const std::vector<double>& scales() const { return scales_; }
  const OrbConfig& config() const { return config_; }

  struct CentroidWeights;  ///< SIMD weights of the orientation patch (orb_extractor.cpp)

 private:
  /// Selects this level's corners (level coordinates, octave and response set; angle not yet).
  void detect_level(const cv::Mat& level_image, int budget, std::vector<cv::KeyPoint>& out) const;

  OrbConfig config_;
  std::vector<double> scales_;
  std::vector<int> level_budget_;
  std::vector<int> umax_;                   ///< half-widths of the circular patch used for the orientation
  static constexpr int kSmoothStep = 2048;  ///< row step of the smoothed-level buffer (bytes)
  std::shared_ptr<const CentroidWeights> centroid_weights_;
  std::vector<int> fixed_step_offsets_;  ///< BRIEF pattern offsets for rows kSmoothStep bytes apart
  BriefPattern pattern_;
};

}  // namespace glmbslam::frontend
