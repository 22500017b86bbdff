#pragma once
// Plain types shared by every module.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/StdVector>

namespace glmbslam {

/// Rigid transform T_a_b (maps points from frame b to frame a). Camera poses are T_world_camera.
using Pose3 = Eigen::Isometry3d;
/// A trajectory: one pose per frame.
using PoseList = std::vector<Pose3, Eigen::aligned_allocator<Pose3>>;

/// Rectified stereo pinhole calibration of the left camera plus the stereo baseline (metres, > 0).
struct StereoCalibration {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  double baseline = 0.0;  ///< distance between the camera centres; right camera at +baseline along x
  int width = 0;          ///< image width in pixels
  int height = 0;         ///< image height in pixels
};

}  // namespace glmbslam
