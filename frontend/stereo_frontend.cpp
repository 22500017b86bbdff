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

namespace {

void require_same_size(const cv::Mat& left, const cv::Mat& right) {
  if (!left.empty() && !right.empty() && left.size() != right.size()) {
    throw InputError("stereo frame", "left image is " + std::to_string(left.cols) + "x" +
                                         std::to_string(left.rows) + " but right image is " +
                                         std::to_string(right.cols) + "x" + std::to_string(right.rows));
  }
}

}  // namespace

StereoFrameFeatures StereoFrontend::process(const cv::Mat& left, const cv::Mat& right) const {
  require_same_size(left, right);
  return process([&] { return left; }, [&] { return right; });
}

StereoFrameFeatures StereoFrontend::process(const std::function<cv::Mat()>& load_left,
                                            const std::function<cv::Mat()>& load_right) const {
  StereoFrameFeatures f;
  cv::Mat left, right;
  Stopwatch sw;
  if (!right_worker_) {
    left = load_left();
    right = load_right();
    require_same_size(left, right);
    f.left = left_extractor_.extract(left);  // an empty image gives no features
    f.right = right_extractor_.extract(right);
  } else {
    auto right_job = right_worker_->submit([&] {
      right = load_right();
      return right_extractor_.extract(right);
    });
    try {
      left = load_left();
      f.left = left_extractor_.extract(left);
    } catch (...) {
      right_job.wait();  // the job refers to this frame's locals
      throw;
    }
    f.right = right_job.get();
    require_same_size(left, right);
  }
  f.extract_ms = sw.elapsed_ms();
  match(f);
  return f;
}

void StereoFrontend::match(StereoFrameFeatures& f) const {
  Stopwatch sw;
  f.measurements = matcher_.match(f.left, f.right, &f.left_to_measurement, &f.stats);
  f.match_ms = sw.elapsed_ms();
}

}  // namespace glmbslam::frontend
