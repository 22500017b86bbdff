#include "frontend/stereo_frontend.hpp"

#include <future>
#include <string>

#include "core/error.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::frontend {

StereoFrontend::StereoFrontend(const StereoCalibration& calibration, const FrontendConfig& config)
    : config_(config),
      left_extractor_(config.orb),
      right_extractor_(config.orb),
      matcher_(StereoCamera(calibration), config.stereo, left_extractor_.scales()),
      right_worker_(config.orb.parallel ? std::make_shared<WorkerThread>() : nullptr) {}

StereoFrameFeatures StereoFrontend::process(const cv::Mat& left, const cv::Mat& right) const {
  if (!left.empty() && !right.empty() && left.size() != right.size()) {
    throw InputError("stereo frame", "left image is " + std::to_string(left.cols) + "x" +
                                         std::to_string(left.rows) + " but right image is " +
                                         std::to_string(right.cols) + "x" + std::to_string(right.rows));
  }
  StereoFrameFeatures f;
  Stopwatch sw;
  if (right_worker_ && !left.empty() && !right.empty()) {
    auto right_job = right_worker_->submit([&] { return right_extractor_.extract(right); });
    f.left = left_extractor_.extract(left);
    f.right = right_job.get();
  } else {
    f.left = left_extractor_.extract(left);
    f.right = right_extractor_.extract(right);
  }
  f.extract_ms = sw.elapsed_ms();
  sw.restart();
  f.measurements = matcher_.match(f.left, f.right, &f.left_to_measurement, &f.stats);
  f.match_ms = sw.elapsed_ms();
  return f;
}

}  // namespace glmbslam::frontend
