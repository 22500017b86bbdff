#include "io/stereo_rectification.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.hpp"

namespace glmbslam::io {

namespace {

cv::Matx33d camera_matrix(const EurocCameraSensor& s) {
  return cv::Matx33d(s.fu, 0.0, s.cu, 0.0, s.fv, s.cv, 0.0, 0.0, 1.0);
}

}  // namespace

StereoRectification::StereoRectification(const EurocCameraSensor& left, const EurocCameraSensor& right,
                                         const std::string& right_path) {
  if (left.width != right.width || left.height != right.height) {
    throw InputError(right_path, "resolution differs from the left camera's");
  }
  // x_right = R x_left + T: the left camera frame expressed in the right one.
  const Pose3 T_right_left = right.T_BS.inverse() * left.T_BS;
  cv::Matx33d R;
  cv::Vec3d T;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = T_right_left.linear()(r, c);
    T[r] = T_right_left.translation()(r);
  }
  const cv::Size size(left.width, left.height);
  const cv::Mat K0(camera_matrix(left)), K1(camera_matrix(right));
  const cv::Mat D0(left.distortion, true), D1(right.distortion, true);
  cv::Mat R1, R2, P1, P2, Q;
  cv::stereoRectify(K0, D0, K1, D1, size, cv::Mat(R), cv::Mat(T), R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY,
                    0.0, size);
  calibration_.fx = P1.at<double>(0, 0);
  calibration_.fy = P1.at<double>(1, 1);
  calibration_.cx = P1.at<double>(0, 2);
  calibration_.cy = P1.at<double>(1, 2);
  calibration_.baseline = -P2.at<double>(0, 3) / P2.at<double>(0, 0);
  calibration_.width = left.width;
  calibration_.height = left.height;
  if (!(calibration_.baseline > 0.0) ||
      std::abs(P2.at<double>(1, 3)) > 1e-6 * std::abs(P2.at<double>(0, 3))) {
    throw InputError(right_path,
                     "the right camera is not to the right of the left one (not a horizontal "
                     "stereo pair)");
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R_left_(r, c) = R1.at<double>(r, c);
  cv::initUndistortRectifyMap(K0, D0, R1, P1, size, CV_32FC1, left_x_, left_y_);
  cv::initUndistortRectifyMap(K1, D1, R2, P2, size, CV_32FC1, right_x_, right_y_);
}

cv::Mat StereoRectification::rectify_left(const cv::Mat& raw) const {
  cv::Mat out;
  cv::remap(raw, out, left_x_, left_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  return out;
}

cv::Mat StereoRectification::rectify_right(const cv::Mat& raw) const {
  cv::Mat out;
  cv::remap(raw, out, right_x_, right_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  return out;
}

}  // namespace glmbslam::io
