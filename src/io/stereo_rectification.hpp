#pragma once
// Rectification of a calibrated stereo rig with distortion (EuRoC sensor.yaml pairs): computed once with
// OpenCV (stereoRectify, zero disparity at infinity, only valid pixels kept), then applied to every frame.
#include <opencv2/core.hpp>

#include "core/types.hpp"
#include "io/euroc_files.hpp"

namespace glmbslam::io {

class StereoRectification {
 public:
  /// `left`, `right`: the two cameras' calibrations (T_BS in a common body frame). Throws InputError naming
  /// `right_path` if the right camera is not to the right of the left one after rectification, or the two
  /// resolutions differ.
  StereoRectification(const EurocCameraSensor& left, const EurocCameraSensor& right,
                      const std::string& right_path);

  /// The rectified pinhole pair (left intrinsics, baseline, image size).
  const StereoCalibration& calibration() const { return calibration_; }
  /// Rotation of the rectified left camera frame relative to the unrectified left camera: x_rect = R · x_cam.
  const Eigen::Matrix3d& rotation_left() const { return R_left_; }
  /// The rectified left / right image of a raw 8-bit image of the calibrated size.
  cv::Mat rectify_left(const cv::Mat& raw) const;
  cv::Mat rectify_right(const cv::Mat& raw) const;

 private:
  StereoCalibration calibration_;
  Eigen::Matrix3d R_left_ = Eigen::Matrix3d::Identity();
  cv::Mat left_x_, left_y_, right_x_, right_y_;
};

}  // namespace glmbslam::io
