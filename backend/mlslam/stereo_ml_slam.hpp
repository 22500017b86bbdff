#pragma once
// RFS maximum-likelihood SLAM (paper 004) on stereo sequences: RfsMlSlam (rfs_ml_slam.hpp) with SE(3) poses
// driven by the VO controls (backend/models/se3_motion.hpp, covariance Q_k) and (u_L, v, u_R) measurements
// (backend/models/stereo_measurement_model.hpp). Used as the refinement of the stereo filter's trajectory and
// map (a sliding window online, a full pass at the end).
#include <cmath>

#include "backend/mlslam/ceres_factors_2d.hpp"
#include "backend/mlslam/ceres_factors_3d.hpp"
#include "backend/mlslam/rfs_ml_slam.hpp"
#include "backend/mlslam/smooth_stereo_detection.hpp"
#include "backend/models/se3_motion.hpp"
#include "backend/models/stereo_measurement_model.hpp"

namespace glmbslam::backend {

/// The stereo parts of RfsMlSlam: pose blocks (quaternion, translation) on Pose3CeresManifold, the
/// relative-pose and stereo projection factors of ceres_factors_3d.hpp, p_D smooth in depth and at the image
/// borders (border_range_m: the depth width, border_pixels: the image-border width).
struct StereoMlSlamParts {
  using Pose = Pose3;
  using Detection = SmoothStereoDetection;
  using Manifold = Pose3CeresManifold;
  static constexpr int kBlockSize = kPose3BlockSize;
  static Detection detection(const StereoMeasurementModel& model, const MlSlamConfig& c) {
    return Detection(model, c.border_range_m, c.border_pixels);
  }
  /// Default birth and merge distances are 10× this: 5 cm.
  static double length_scale(const StereoMeasurementModel& /*model*/) { return 0.05; }
  static void to_block(const Pose3& x, double* block) { pose3_to_block(x, block); }
  static Pose3 from_block(const double* block) { return pose3_from_block(block); }
  static ceres::CostFunction* motion_factor(const Se3Motion& /*motion*/, const RelativePoseControl& u,
                                            const Matrix6d& W, const Pose3& /*prev*/, double scale) {
    return make_relative_pose_factor(u.delta, W / std::sqrt(scale));
  }
  static ceres::CostFunction* measurement_factor(const StereoMeasurementModel& model,
                                                 const Eigen::Vector3d& z, const Eigen::Matrix3d& W,
                                                 double beta) {
    return make_stereo_measurement_factor(model.camera(), z, W, beta);
  }
};

using StereoMlSlam = RfsMlSlam<Se3Motion, StereoMeasurementModel, StereoMlSlamParts>;

}  // namespace glmbslam::backend
