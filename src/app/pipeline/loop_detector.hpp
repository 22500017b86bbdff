#pragma once
// Revisit detection for the refinement's loop closing (refine.loop_closure): the filter never associates a
// measurement with a landmark mapped long ago once its pose has drifted further than the gate, so nothing
// ever pulls a revisit back. Every few frames a keyframe keeps its stereo points (left-camera frame, near
// ones only) and their ORB descriptors. At the end, each keyframe is compared with the earlier keyframes near
// its position on the trajectory it is given, the final pass's start (refine.final_start), within a radius
// that grows with the path travelled between them, as drift does, and facing the same way: descriptors
// matched by Hamming distance with a ratio test, a relative pose by RANSAC over 3-point Umeyama fits scored
// by reprojection in the earlier stereo pair, then Gauss–Newton on the inliers' stereo reprojection error.
// Accepted revisits become loop constraints of the pose graph (backend/mlslam/loop_pose_graph.hpp).
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

#include "backend/mlslam/loop_pose_graph.hpp"
#include "core/stereo_camera.hpp"
#include "core/types.hpp"
#include "frontend/stereo_measurement.hpp"

namespace glmbslam::app {

/// refine.loop_* settings (config/kitti00-02.yaml documents each).
struct LoopDetectorOptions {
  std::size_t keyframe_every = 5;     ///< a keyframe every this many frames
  std::size_t min_gap_frames = 100;   ///< a revisit is at least this many frames later
  double search_radius_m = 10.0;      ///< candidates within this distance on the trajectory …
  double search_radius_per_m = 0.02;  ///< … plus this fraction of the path travelled in between (drift)
  double max_search_radius_m = 50.0;  ///< cap of the radius
  double max_view_angle_deg = 45.0;   ///< optical axes at most this far apart
  std::size_t candidates = 3;         ///< nearest candidates tried per keyframe
  double max_depth_m = 25.0;          ///< keyframe points farther than this are not kept
  std::size_t max_points = 300;       ///< strongest-response points kept per keyframe
  int max_hamming = 50;               ///< descriptor distance of an accepted match
  double ratio = 0.8;                 ///< best / second-best distance of an accepted match
  double inlier_px = 3.0;             ///< stereo reprojection error (each of u_L, v, u_R) of an inlier
  int ransac_iterations = 200;
  std::size_t min_inliers = 40;       ///< inliers of an accepted revisit
  double sigma_translation_m = 0.05;  ///< the loop constraint's standard deviations
  double sigma_rotation_rad = 0.005;
};

/// One keyframe: its frame position in the run and its stereo points with their descriptors. The stereo
/// measurement of a point is its projection (the point was triangulated from it), so it is not kept.
struct LoopKeyframe {
  std::size_t k = 0;
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> points;  ///< left camera frame
  std::vector<std::array<std::uint8_t, 32>> descriptors;
};

/// The relative pose T_ab (x_a⁻¹ x_b: b's camera in a's frame) of two keyframes and its inlier count, if
/// they see the same place (≥ min_inliers). `seed` makes the RANSAC reproducible.
struct KeyframeMatch {
  Pose3 T_ab = Pose3::Identity();
  std::size_t inliers = 0;
};
std::optional<KeyframeMatch> match_keyframes(const LoopKeyframe& a, const LoopKeyframe& b,
                                             const StereoCamera& camera, const LoopDetectorOptions& options,
                                             std::uint64_t seed);

class LoopDetector {
 public:
  LoopDetector(const LoopDetectorOptions& options, const StereoCalibration& calibration);

  /// Frame k of the run with its stereo measurements (a keyframe every keyframe_every frames).
  void add_frame(std::size_t k, const frontend::StereoMeasurementList& measurements);

  /// The revisits along `trajectory` (one pose per frame of the run, the filter's), as loop constraints.
  std::vector<backend::LoopConstraint> detect(const PoseList& trajectory) const;

  std::size_t keyframes() const { return keyframes_.size(); }

 private:
  LoopDetectorOptions options_;
  StereoCamera camera_;
  std::vector<LoopKeyframe> keyframes_;
};

}  // namespace glmbslam::app
