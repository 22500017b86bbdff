#pragma once
// Facade of the stereo frontend: ORB on both images (concurrently), stereo matching and triangulation.
#include <functional>
#include <memory>

#include <opencv2/core.hpp>

#include "core/types.hpp"
#include "core/worker_thread.hpp"
#include "frontend/frontend_config.hpp"
#include "frontend/orb_extractor.hpp"
#include "frontend/stereo_matcher.hpp"

namespace glmbslam::frontend {

/// Everything the frontend knows about one stereo frame.
struct StereoFrameFeatures {
  OrbFeatures left;
  OrbFeatures right;
  StereoMeasurementList measurements;    ///< one per accepted stereo match, in left-keypoint order
  std::vector<int> left_to_measurement;  ///< per left keypoint: index into measurements or −1
  StereoMatchStats stats;
  /// Wall time of the ORB extraction of both images (given loaders: their loading included).
  double extract_ms = 0.0;
  double match_ms = 0.0;  ///< wall time of stereo matching and triangulation
};

class StereoFrontend {
 public:
  StereoFrontend(const StereoCalibration& calibration, const FrontendConfig& config);

  /// Processes a rectified pair. An empty left or right image is treated as a blank image: the frame gets the
  /// features of the other image (if any) and no stereo measurements, so the VO falls back for that frame.
  /// Throws InputError("stereo frame", …) if both images are non-empty and differ in size.
  StereoFrameFeatures process(const cv::Mat& left, const cv::Mat& right) const;
  /// The same for a pair produced by two loaders, each called on the thread that extracts its image: with
  /// config.orb.parallel the right image's decoding (and rectification) overlaps the left one's instead of
  /// preceding it. An exception of either loader propagates, after the other side has finished.
  StereoFrameFeatures process(const std::function<cv::Mat()>& load_left,
                              const std::function<cv::Mat()>& load_right) const;

  const StereoCamera& camera() const { return matcher_.camera(); }
  const OrbExtractor& extractor() const { return left_extractor_; }

 private:
  /// Stereo matching and triangulation of f.left against f.right.
  void match(StereoFrameFeatures& f) const;

  FrontendConfig config_;
  OrbExtractor left_extractor_;
  OrbExtractor right_extractor_;
  StereoMatcher matcher_;
  /// With config.orb.parallel: the persistent thread that extracts the right image while the caller extracts
  /// the left one (shared by copies; jobs are queued, so concurrent callers stay correct).
  std::shared_ptr<WorkerThread> right_worker_;
};

}  // namespace glmbslam::frontend
