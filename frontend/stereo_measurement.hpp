#pragma once
// One stereo measurement handed to the backend: plain Eigen, no OpenCV (the backend must not depend on it).
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

#include "core/hamming.hpp"

namespace glmbslam::frontend {

/// A left keypoint matched to a right keypoint on the same rectified row and triangulated.
struct StereoMeasurement {
  /// z = (u_L, v, u_R) in pixels of the rectified images (v shared by both images).
  Eigen::Vector3d z = Eigen::Vector3d::Zero();
  /// Standard deviation (pixels) of each coordinate of z: pixel_sigma · scale_factor^octave, isotropic.
  double pixel_sigma = 1.0;
  /// Triangulated point in the left camera frame (x right, y down, z forward), metres.
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  /// Covariance of `point`, J · diag(σ²) · Jᵀ with J = ∂point/∂z (first-order propagation of pixel noise).
  Eigen::Matrix3d point_covariance = Eigen::Matrix3d::Identity();
  /// 256-bit ORB descriptor of the left keypoint.
  std::array<std::uint8_t, 32> descriptor{};
  int octave = 0;          ///< pyramid level of the left keypoint
  float response = 0.0f;   ///< FAST corner score of the left keypoint
  float angle_deg = 0.0f;  ///< ORB orientation of the left keypoint, degrees
  int left_index = -1;     ///< index of the left keypoint in its frame's keypoint list
  int right_index = -1;    ///< index of the matched right keypoint
};

using StereoMeasurementList = std::vector<StereoMeasurement, Eigen::aligned_allocator<StereoMeasurement>>;

/// Hamming distance between 256-bit descriptors (src/core/hamming.hpp, shared with the backend).
using glmbslam::hamming_distance;

}  // namespace glmbslam::frontend
