#pragma once
// ORB features spread over the image: FAST corners are detected per grid cell on every pyramid level (with a
// lower threshold in cells where the normal one finds nothing), each level keeps its share of the feature
// budget by taking the strongest corner of every cell in turn (round robin over cells), orientations come
// from the intensity centroid, and descriptors from cv::ORB::compute.
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

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
  /// no features. Not thread-safe for one object; use one extractor per concurrent image.
  OrbFeatures extract(const cv::Mat& image) const;

  /// scale_factor^level for each level.
  const std::vector<double>& scales() const { return scales_; }
  const OrbConfig& config() const { return config_; }

 private:
  void detect_level(const cv::Mat& level_image, int level, int budget, std::vector<cv::KeyPoint>& out) const;

  OrbConfig config_;
  std::vector<double> scales_;
  std::vector<int> level_budget_;
  std::vector<int> umax_;  ///< half-widths of the circular patch used for the orientation
  cv::Ptr<cv::ORB> orb_;
};

}  // namespace glmbslam::frontend
