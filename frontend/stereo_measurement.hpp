#pragma once
// One stereo measurement handed to the backend: plain Eigen, no OpenCV (the backend must not depend on it).
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

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

/// Hamming distance between two 256-bit descriptors. Without the POPCNT instruction in the target flags the
/// compiler's popcount builtin becomes a library call, so the bits are counted in parallel (SWAR) instead.
inline int hamming_distance(const std::uint8_t* a, const std::uint8_t* b) {
#if defined(__POPCNT__) || !(defined(__x86_64__) || defined(__i386__))
  int d = 0;
  for (int i = 0; i < 32; i += 8) {
    std::uint64_t x, y;
    __builtin_memcpy(&x, a + i, 8);
    __builtin_memcpy(&y, b + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
#else
  std::uint64_t bytes = 0;  // per-byte bit counts of the four words (each byte ends ≤ 32)
  for (int i = 0; i < 32; i += 8) {
    std::uint64_t x, y;
    __builtin_memcpy(&x, a + i, 8);
    __builtin_memcpy(&y, b + i, 8);
    x ^= y;
    x -= (x >> 1) & 0x5555555555555555ULL;
    x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
    bytes += (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
  }
  return static_cast<int>((bytes * 0x0101010101010101ULL) >> 56);
#endif
}

}  // namespace glmbslam::frontend
